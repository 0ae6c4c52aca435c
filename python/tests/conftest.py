"""Shared fixtures: boards standing in the posture of a planned tripod gait.

Every test runs on the in-process virtual robot (``Board.open("virtual")``): the firmware
library's controller and link dispatcher over simulated servos and a simulated clock, so the tests
need no hardware and run faster than real time. The closed-loop tests also run on the emulated
board: the release firmware image in the RP2040 emulator with 22 virtual servos on its bus, started
by ``hil-emulator`` (hil-tests/src/bin/hil-emulator.rs) for the session, reached through its pty.
With ``DBOT_TEST_PORT`` set they run on that port as well (a board's ``/dev/ttyACM0``).

The emulator needs the firmware image, ``hil-emulator`` and ``hil-bus``, the runner's Node packages
and defmt-print. Without them its tests fail with the reason (the test command must run them);
``DBOT_HIL_OPTIONAL=1`` skips them instead on a developer's machine (scripts/test.sh unsets it).
Tests on a real board (``DBOT_TEST_PORT``) are opt-in and say so when skipped.

Time on a port is not the host's: the emulator runs at roughly 0.15 x real time while the bus
cycles with 22 servos (faster when idle) and a real board at 1 x. So waits here are counted in the
board's own bus cycles or driven by its proprioception, never by the host's wall clock; the wall
clock only bounds how long a test may hang (generously). The emulator runs freely: a test
descheduled by a loaded machine for longer than a stream's setpoint timeout (in the board's
cycles) still trips it. ``hil-emulator --paced-by PID`` would stop the board's clock while the
host computes, but on a machine loaded to about 20 runnable processes per core it slowed the
emulator to about 0.014 x real time (every wake-up of the host waits for a CPU), past the wall
bound below, so it is not used here.
"""

from __future__ import annotations

import importlib
import os
import pathlib
import select
import subprocess
import time

import numpy as np
import pytest

import dbot

ROOT = pathlib.Path(__file__).resolve().parents[2]
#: Exit status of hil-emulator when a prerequisite is missing (hil-emulator.rs, `MISSING`).
HIL_EMULATOR_MISSING = 3
#: Wall-clock bound for anything on a port (a wedged emulator fails a test instead of hanging CI).
PORT_WALL_S = 180.0

def need_module(name: str):
    """Imports `name` for a test that needs it; missing, fails saying what installs it (a test that
    cannot run must not pass by skipping)."""
    try:
        return importlib.import_module(name)
    except ModuleNotFoundError:
        pytest.fail(
            f"the Python package `{name}` is missing: `pip install './python[test]'` installs "
            "what the tests need (scripts/setup.d/40-python.sh does in the repository's .venv)",
            pytrace=False,
        )


@pytest.fixture(scope="session")
def model() -> dbot.Model:
    return dbot.Model.builtin("drosophibot2")


@pytest.fixture(scope="session")
def tripod_plan(model: dbot.Model) -> dbot.Plan:
    # 50 slices keep the table small; the gait is the default preset's (servo-safe: the paper's
    # table 1 tripod at a 1.0 s swing, 2.5 s per step).
    return dbot.plan(model, slices=50)


def hil_emulator_binary() -> pathlib.Path:
    """`hil-emulator` as `cargo build -p hil-tests --bins` leaves it (`CARGO_TARGET_DIR` is
    honoured), or `DBOT_HIL_EMULATOR`."""
    if os.environ.get("DBOT_HIL_EMULATOR"):
        return pathlib.Path(os.environ["DBOT_HIL_EMULATOR"])
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    return target / "debug" / "hil-emulator"


def missing_prerequisite(why: str) -> None:
    """Fails the test with `why` (the test command must run the emulator tests), or skips it when
    ``DBOT_HIL_OPTIONAL`` is set to something other than 0 (an explicit opt-out)."""
    if os.environ.get("DBOT_HIL_OPTIONAL", "0") in ("", "0"):
        pytest.fail(
            f"cannot run on the emulated board: {why} (scripts/setup.d/30-hil.sh installs the "
            "prerequisites; DBOT_HIL_OPTIONAL=1 skips these tests instead)",
            pytrace=False,
        )
    pytest.skip(f"emulated board not available (DBOT_HIL_OPTIONAL is set): {why}")


@pytest.fixture(scope="session")
def emulator_port(tmp_path_factory) -> str:
    """Starts `hil-emulator` (22 virtual servos at 1 Mbit/s) for the session; yields its pty.
    Its stderr (the firmware's defmt log with simulated times) goes to a file that is printed
    when the emulator cannot start."""
    exe = hil_emulator_binary()
    if not exe.is_file():
        missing_prerequisite(f"no {exe} (build it with `cargo build -p hil-tests --bins`)")
    log_path = tmp_path_factory.mktemp("hil-emulator") / "emulator.log"
    log = open(log_path, "w+b")
    proc = subprocess.Popen(
        [str(exe), "--log"], stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=log, cwd=ROOT
    )
    try:
        line = b""
        deadline = time.monotonic() + PORT_WALL_S
        while not line.endswith(b"\n") and time.monotonic() < deadline:
            ready, _, _ = select.select([proc.stdout], [], [], 0.5)
            if ready:
                chunk = os.read(proc.stdout.fileno(), 256)
                if not chunk:
                    break
                line += chunk
        if not line.startswith(b"PORT "):
            try:
                rc = proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                rc = None
            log.seek(0)
            tail = log.read().decode(errors="replace")[-2000:]
            if rc == HIL_EMULATOR_MISSING:
                missing_prerequisite(tail.strip())
            pytest.fail(f"hil-emulator did not report its port (exit status {rc}):\n{tail}")
        yield line.decode().split(maxsplit=1)[1].strip()
    finally:
        # Closing stdin is hil-emulator's stop signal; it ends the runner and the servo chain.
        proc.stdin.close()
        try:
            proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            proc.terminate()
            proc.wait(timeout=15)
        log.close()


#: Boards the closed-loop tests run on: "emulator" stands for the pty of `emulator_port`.
PORTS = ["virtual", "emulator"] + (
    [os.environ["DBOT_TEST_PORT"]] if os.environ.get("DBOT_TEST_PORT") else []
)


@pytest.fixture(params=PORTS)
def port(request) -> str:
    if request.param == "emulator":
        return request.getfixturevalue("emulator_port")
    return request.param


_OPEN: list[dbot.Board] = []


def open_board(port: str) -> dbot.Board:
    """Opens `port`; the board is closed after the test (a serial port is exclusive). On a port
    a reply may take PORT_WALL_S of wall time: the emulator on a loaded machine runs far slower
    than the library's default of 2 s allows for an upload's commit (flash erase and program),
    and the wall clock only bounds a hang here."""
    if port.startswith("virtual"):
        board = dbot.Board.open(port)
    else:
        board = dbot.Board.open(port, reply_timeout_s=PORT_WALL_S)
    _OPEN.append(board)
    return board


@pytest.fixture(autouse=True)
def _close_boards():
    yield
    while _OPEN:
        _OPEN.pop().close()


def bus_cycles(board: dbot.Board) -> int:
    """The board's bus cycle counter (every cycle counts, whatever the state): its own clock."""
    cycles = board.status()["counters"]["cycles"]
    assert isinstance(cycles, int), f"the board's cycle counter is not an integer: {cycles!r}"
    return cycles


def wall_deadline(board: dbot.Board) -> float | None:
    """The monotonic wall time after which a wait on `board` gives up; None on the virtual robot,
    where time only passes while the host waits, so a simulated budget bounds every wait."""
    return None if board.port.startswith("virtual") else time.monotonic() + PORT_WALL_S


def wait_cycles(board: dbot.Board, cycles: int) -> None:
    """Lets at least `cycles` bus cycles pass on the board (proprioception and telemetry that
    arrive meanwhile are kept)."""
    target = bus_cycles(board) + cycles
    deadline = wall_deadline(board)
    while (n := bus_cycles(board)) < target:
        if deadline is not None and time.monotonic() > deadline:
            raise AssertionError(f"the board ran {n} of {target} bus cycles in {PORT_WALL_S} s")
        board.wait(0.01)


def wait_for_state(board: dbot.Board, states: tuple[str, ...], max_cycles: int) -> dict:
    """Polls the status until the board is in one of `states`, for at most `max_cycles` bus
    cycles of the board; returns that status."""
    limit = bus_cycles(board) + max_cycles
    deadline = wall_deadline(board)
    while True:
        st = board.status()
        if st["state"] in states:
            return st
        n = bus_cycles(board)
        late = deadline is not None and time.monotonic() > deadline
        if n > limit or late:
            raise AssertionError(f"not {' or '.join(states)} within {max_cycles} bus cycles: {st}")
        board.wait(0.01)


def record_timeout(board: dbot.Board) -> float:
    """How long to wait for the next proprioception record, s of the board's clock as the host
    sees it: simulated on the virtual robot (one record per 10 ms cycle, so 1 s is 100 cycles),
    wall on a port, where the emulator may be 20 x slower than real time on a loaded machine."""
    return 1.0 if board.port.startswith("virtual") else 20.0


def upload(board: dbot.Board, plan: dbot.Plan) -> None:
    """Uploads `plan` into slot 0. The emulated board (firmware image in rp2040js) reports
    ServoMissing while its flash is written (bus cycles stall): that fault is cleared here.
    Seen only on the emulator; see the report of the python branch."""
    board.upload_plan(0, plan)
    wait_cycles(board, 30)
    if board.status()["state"] == "Fault":
        board.clear_fault()
        wait_cycles(board, 30)


def bus_baud(cycle_hz: int) -> int:
    """The lowest MX(2.0) baud whose wire time leaves 10 % of the period spare: a 22-servo cycle is
    622 bytes of 10 bits (dynamixel.md), 6.22 ms at 1 Mbit/s, so 100 Hz fits 1 Mbit/s and 200 Hz
    needs 2 Mbit/s. A real robot's servos must be set to that baud first (`dbot dxl setup`)."""
    for baud in (1_000_000, 2_000_000, 3_000_000, 4_000_000):
        if 622 * 10 / baud <= 0.9 / cycle_hz:
            return baud
    raise ValueError(f"{cycle_hz} Hz does not fit the bus even at 4 Mbit/s")


def standing_board(plan: dbot.Plan, cycle_hz: int = 100, port: str = "virtual") -> dbot.Board:
    """A board with `plan` in slot 0, played for one step so it stands in the gait's posture
    (streaming may only start from standing), at `cycle_hz` bus cycles per second. A real or
    emulated board left in a fault or streaming by an earlier test is brought back first."""
    board = open_board(port)
    state = board.status()["state"]
    if state == "Fault":
        board.clear_fault()
    elif state in ("Streaming", "Walking", "Ramping", "Stopping"):
        board.stop()
        wait_for_state(board, ("Standing", "Idle"), max_cycles=30 * cycle_hz)
    board.set_bus(bus_baud(cycle_hz), cycle_hz)
    upload(board, plan)
    board.play(0, steps=1)
    # A ramp to the first posture plus one step (2.5 s for the default plan): 10 s is ample.
    wait_for_state(board, ("Standing",), max_cycles=10 * cycle_hz)
    return board


def servo_rest(plan: dbot.Plan, model: dbot.Model) -> np.ndarray:
    """The gait's first slice at the servo joints (joint-map order), rad."""
    return plan.angles[0, model.servo_joints]


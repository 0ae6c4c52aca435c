"""Shared fixtures: a virtual robot standing in the posture of a planned tripod gait.

Every test here runs on the in-process virtual robot (``Board.open("virtual")``): the firmware
library's controller and link dispatcher over simulated servos and a simulated clock, so the tests
need no hardware and run faster than real time. The closed-loop tests also run against the port in
``DBOT_TEST_PORT`` when it is set (a board's ``/dev/ttyACM0`` or the RP2040 emulator's pty).
"""

from __future__ import annotations

import os

import numpy as np
import pytest

import dbot


@pytest.fixture(scope="session")
def model() -> dbot.Model:
    return dbot.Model.builtin("drosophibot2")


@pytest.fixture(scope="session")
def tripod_plan(model: dbot.Model) -> dbot.Plan:
    # 50 slices keep the table small; the gait is the paper's table 1 tripod.
    return dbot.plan(model, slices=50)


#: Ports the closed-loop tests run on.
PORTS = ["virtual"] + ([os.environ["DBOT_TEST_PORT"]] if os.environ.get("DBOT_TEST_PORT") else [])


@pytest.fixture(params=PORTS)
def port(request) -> str:
    return request.param


_OPEN: list[dbot.Board] = []


def open_board(port: str) -> dbot.Board:
    """Opens `port`; the board is closed after the test (a serial port is exclusive)."""
    board = dbot.Board.open(port)
    _OPEN.append(board)
    return board


@pytest.fixture(autouse=True)
def _close_boards():
    yield
    while _OPEN:
        _OPEN.pop().close()


def upload(board: dbot.Board, plan: dbot.Plan) -> None:
    """Uploads `plan` into slot 0. The emulated board (firmware image in rp2040js) reports
    ServoMissing while its flash is written (bus cycles stall): that fault is cleared here.
    Seen only on the emulator; see the report of the python branch."""
    board.upload_plan(0, plan)
    board.wait(0.3)
    if board.status()["state"] == "Fault":
        board.clear_fault()
        board.wait(0.3)


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
    elif state in ("Streaming", "Walking", "Ramping"):
        board.stop()
        board.wait(2.0)
    board.set_bus(bus_baud(cycle_hz), cycle_hz)
    upload(board, plan)
    board.play(0, steps=1)
    for _ in range(100):
        board.wait(0.1)
        if board.status()["state"] == "Standing":
            return board
    raise AssertionError(f"the virtual robot never stood: {board.status()}")


def servo_rest(plan: dbot.Plan, model: dbot.Model) -> np.ndarray:
    """The gait's first slice at the servo joints (joint-map order), rad."""
    return plan.angles[0, model.servo_joints]

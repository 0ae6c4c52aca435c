"""Closed loop on the virtual robot and on the emulated board (the release firmware image in the
RP2040 emulator, see conftest.py): setpoints streamed from Python, servos follow, the
setpoint-loss rule (hold for `timeout_cycles`, then safe with `SetpointTimeout`) when the stream
stops, and streaming only from standing. The loops are driven by the board's proprioception (the
next setpoint goes out when a cycle's record arrives), so they run the same on simulated time,
on the emulator's slower-than-real time and on a real board.

Tolerances: the virtual servos are the dynamixel crate's chain (dynamixel/src/sim/physics.rs): a
quasi-static DC motor behind the MX position P controller. Below PWM saturation (errors under
885 / (P / 128) = 133 ticks = 0.20 rad at P = 850) that is a first-order lag towards the goal with
time constant tau = 1 / (omega_0 * k), k = (P / 128) / 885 per tick = 4.89 per rad, omega_0 the
no-load speed: MX-28 (55 rpm = 5.76 rad/s) tau = 35.5 ms, MX-64 (63 rpm) tau = 31.0 ms. The wire
carries angles in 1e-4 rad and positions in servo ticks (2 pi / 4096 = 1.53e-3 rad). A goal held
for 0.3 s (over 8 time constants of the slower MX-28, residual e^-8.4 = 2e-4 of the step) must be
reached to within FOLLOW_TOL = 5e-3 rad: about three ticks, i.e. quantisation with margin.
"""

from __future__ import annotations

import numpy as np
import pytest

import dbot
from conftest import (
    open_board,
    record_timeout,
    servo_rest,
    standing_board,
    upload,
    wait_cycles,
    wait_for_state,
)

FOLLOW_TOL = 5e-3  # rad, see the module docstring
TICK = 2 * np.pi / 4096
#: Time constant of the slower servo model (MX-28 at P gain 850), s; see the module docstring.
TAU_MX28_S = 1.0 / ((55 * 2 * np.pi / 60) * (850 / 128) / 885 / TICK)
#: Setpoint timeout while following: not what the test is about, so long enough (5 s at 100 Hz;
#: about 30 s of wall time on the emulator, which runs at about 0.15 x real time) that a host
#: descheduled by a loaded machine does not trip it on a port (0.5 s did, under load).
FOLLOW_TIMEOUT_CYCLES = 500


def stream_constant(board: dbot.Board, target: np.ndarray, cycles: int) -> list[dict]:
    """Sends `target` once per bus cycle for `cycles` cycles; returns the proprioception (and
    stores the last setpoint's number in `stream_constant.last_seq`)."""
    out = []
    timeout = record_timeout(board)
    for _ in range(cycles):
        stream_constant.last_seq = board.send_setpoint(target)
        rec = board.next_proprioception(timeout_s=timeout)
        assert rec is not None, f"no proprioception within {timeout} s: {board.status()}"
        out.append(rec)
    return out


def test_streaming_is_refused_unless_standing(tripod_plan, port) -> None:
    board = open_board(port)
    if board.status()["state"] == "Fault":
        board.clear_fault()
    upload(board, tripod_plan)
    board.play(0, steps=None)
    wait_cycles(board, 5)
    # Moving (ramping to the gait's first posture or walking): streaming must not start.
    assert board.status()["state"] in ("Ramping", "Walking")
    with pytest.raises(dbot.BoardError, match="EnterStreaming"):
        board.enter_streaming()
    assert board.status()["state"] in ("Ramping", "Walking")
    # Once it stands (stop: at the end of the step), it may.
    board.stop()
    wait_for_state(board, ("Standing",), max_cycles=1000)
    board.enter_streaming(timeout_cycles=FOLLOW_TIMEOUT_CYCLES)
    assert board.status()["state"] == "Streaming"
    board.leave_streaming()
    assert board.status()["state"] == "Standing"


def test_servos_follow_streamed_setpoints(tripod_plan, model, port) -> None:
    board = standing_board(tripod_plan, port=port)
    board.enter_streaming(timeout_cycles=FOLLOW_TIMEOUT_CYCLES)
    assert board.status()["state"] == "Streaming"
    rest = servo_rest(tripod_plan, model)
    # A step of +0.1 rad on every joint (within the limits of the gait's first posture) ...
    target = rest + 0.1
    recs = stream_constant(board, target, 30)  # 0.3 s at 100 Hz
    last = recs[-1]
    # ... is on the bus as commanded (to half a servo tick: goals go out in ticks) ...
    assert np.allclose(last["commanded_rad"][0], target, atol=TICK / 2 + 1e-4)
    # ... and the servos have reached it.
    err = np.abs(last["present_rad"][0] - target)
    assert err.max() < FOLLOW_TOL, f"worst joint error {err.max():.4f} rad"
    # While moving, a servo lags its goal: the first record after the step shows the lag.
    first = recs[0]
    assert np.all(np.abs(first["present_rad"][0] - target) > 0.02)
    # A sine on one joint is tracked: on the virtual robot the present angle lags the command by
    # at most one 10 ms bus cycle (d) plus the servo's first-order lag (tau, the MX-28's 35.5 ms
    # bounds the faster MX-64 too; the 0.1 rad swing stays below PWM saturation). The error
    # cmd - pos then has amplitude 0.1 |1 - e^(-j omega d) / (1 + j omega tau)| at omega = 2 pi
    # rad/s: 0.028 rad. Reported positions are whole ticks: plus 2 ticks.
    recs = []
    for k in range(200):
        t = target.copy()
        t[0] += 0.1 * np.sin(2 * np.pi * k / 100)
        seq = board.send_setpoint(t)
        rec = board.next_proprioception(record_timeout(board))
        if port != "virtual":
            # On a port the board's clock runs on while the host computes: records of cycles
            # before this setpoint arrived can still be queued, and sending the next on one of
            # those would put two setpoints in one cycle (the board writes the later): the sine
            # lost its peaks under load. Read on to the first record that carries this one.
            while rec is not None and int(rec["setpoint_seq"][-1]) != seq:
                rec = board.next_proprioception(record_timeout(board))
        assert rec is not None, f"no proprioception at setpoint {k}: {board.status()}"
        recs.append(rec)
    cmd = np.array([r["commanded_rad"][0, 0] for r in recs[100:]])
    pos = np.array([r["present_rad"][0, 0] for r in recs[100:]])
    assert np.ptp(cmd) > 0.19
    if port == "virtual":
        omega, d = 2 * np.pi, 0.01
        lag = 0.1 * abs(1 - np.exp(-1j * omega * d) / (1 + 1j * omega * TAU_MX28_S))
        assert np.abs(cmd - pos).max() < lag + 2 * TICK
    else:
        # Another servo model (the emulator's dxl virtual chain, real servos): the sine is
        # followed, its swing at least 80 % of the command's.
        assert np.ptp(pos) > 0.8 * np.ptp(cmd)


def test_setpoint_loss_holds_then_goes_safe(tripod_plan, model, port) -> None:
    # On the virtual robot time passes only while the host waits: 10 cycles is exact. On a port
    # the board's clock runs while the host is descheduled, so a timeout of 10 cycles (0.1 s of
    # board time) tripped during the stream under load; 100 keeps the hold measurable and the
    # stall margin at about 1 s of board time.
    timeout_cycles = 10 if port.startswith("virtual") else 100
    board = standing_board(tripod_plan, port=port)
    board.enter_streaming(timeout_cycles=timeout_cycles)
    target = servo_rest(tripod_plan, model) - 0.05
    stream_constant(board, target, 20)
    last_seq = stream_constant.last_seq
    # The stream stops. Within ten times the timeout (counted in the board's own bus cycles) the
    # board must have held and gone safe.
    st = wait_for_state(board, ("Fault",), max_cycles=10 * timeout_cycles)
    after = board.drain_proprioception()
    # On a port, records of cycles before the last setpoint took effect can still be queued:
    # the hold starts at the first record that carries the last setpoint.
    seqs = after["setpoint_seq"]
    assert np.any(seqs == last_seq), f"the last setpoint #{last_seq} never showed: {seqs}"
    first = int(np.argmax(seqs == last_seq))
    seqs, ages = seqs[first:], after["setpoint_age"][first:]
    # Hold: the board keeps sending the last setpoint, ageing one cycle at a time up to exactly
    # the timeout (no feedback past it: the board stopped streaming) ...
    assert np.all(seqs == last_seq)
    assert list(ages) == list(range(int(ages[0]), timeout_cycles + 1)), f"ages {ages}"
    assert np.allclose(after["commanded_rad"][first:], target, atol=TICK / 2 + 1e-4)
    # ... then goes safe and says why.
    assert st["fault"] is not None and st["fault"]["kind"] == "SetpointTimeout", st
    # Safe keeps the servos' torque (the robot does not fall): all 22 still on.
    assert st["torque_enabled"] == (1 << 22) - 1
    # Streaming does not start again from the fault: only from standing.
    with pytest.raises(dbot.BoardError, match="EnterStreaming"):
        board.enter_streaming()
    # A setpoint now is not followed: the board is no longer streaming.
    board.send_setpoint(target + 0.2)
    wait_cycles(board, 10)
    assert board.status()["state"] == "Fault"
    assert board.drain_proprioception()["setpoint_seq"].size == 0


def test_bad_setpoints_are_refused_with_the_joint(tripod_plan, model) -> None:
    board = standing_board(tripod_plan)
    board.enter_streaming()
    rest = servo_rest(tripod_plan, model)
    bad = rest.copy()
    bad[7] = 10.0  # beyond the wire's +-3.27 rad
    with pytest.raises(ValueError, match="joint 7"):
        board.send_setpoint(bad)
    with pytest.raises(ValueError, match="torques"):
        board.send_setpoint(rest, torques_nm=np.zeros(3))
    with pytest.raises(ValueError, match="angles_rad"):
        board.send_setpoint("not numbers")


def test_proprioception_every_cycle_with_telemetry_off(tripod_plan, model, port) -> None:
    """Streaming proprioception follows `feedback_every`, not the playback telemetry setting
    (telemetry off used to silence it), and names only setpoints that were sent. The board's
    counters are named integers; its cycle counter and the records' cycle numbers are two
    independent views of the same bus cycles."""
    board = standing_board(tripod_plan, port=port)
    board.set_telemetry(0)
    try:
        before = board.status()["counters"]
        names = {"cycles", "missed_deadlines", "bus_timeouts", "crc_errors", "rejected_frames",
                 "telemetry_dropped", "rate_limited"}
        assert set(before) == names
        assert all(isinstance(v, int) and v >= 0 for v in before.values()), before
        board.enter_streaming(timeout_cycles=FOLLOW_TIMEOUT_CYCLES, feedback_every=1)
        first_seq = None
        recs = []
        timeout = record_timeout(board)
        for _ in range(30):
            seq = board.send_setpoint(servo_rest(tripod_plan, model))
            first_seq = seq if first_seq is None else first_seq
            rec = board.next_proprioception(timeout_s=timeout)
            assert rec is not None, f"telemetry off silenced streaming: {board.status()}"
            recs.append(rec)
        after = board.status()["counters"]
        cycles = np.concatenate([r["cycle"] for r in recs])
        seqs = np.concatenate([r["setpoint_seq"] for r in recs])
        ages = np.concatenate([r["setpoint_age"] for r in recs])
        # One record per bus cycle: consecutive cycle numbers, all within the counter's advance.
        assert np.all(np.diff(cycles) == 1), cycles
        assert before["cycles"] < cycles[0] and cycles[-1] <= after["cycles"]
        # Each names a setpoint of this session (0 = none yet: the standing posture) written
        # for `age` cycles so far, this one included.
        assert np.all((seqs == 0) | ((seqs >= first_seq) & (seqs <= seq))), seqs
        assert np.all(ages >= 1), ages
    finally:
        board.set_telemetry(1)

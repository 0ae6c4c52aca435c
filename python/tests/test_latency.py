"""Latency of streaming on the virtual robot's simulated clock: from the host sending a setpoint
to that setpoint on the bus (the start of the first bus cycle whose goals carry it, reported as the
proprioception record's `time_us` with `setpoint_seq` equal to the setpoint's number). The issue's
bound is two bus cycles, at 100 Hz and at 200 Hz.

The host sends at many offsets within a cycle (0..0.9 of the period after the cycle's start,
evenly spread), so both the best case (just before a cycle starts) and the worst (just after) are
measured. Send times are the board clock at the moment of sending (`Board.now()`, simulated time
on the virtual robot).

One setpoint per cycle: the board applies the newest setpoint at each cycle start, so a second
setpoint sent before the next cycle replaces the first, which then never reaches the bus (by
design, not a loss). The measurement therefore syncs to the newest cycle (stale records drained
first) and sends within that cycle's period. A cycle's record reaches the host only after the
cycle's bus traffic (write, then the servos' replies: a few ms on the wire simulated at 1 Mbit/s),
so an offset shorter than that traffic is sent as soon as the record is in.
"""

from __future__ import annotations

import os

import numpy as np
import pytest

from conftest import servo_rest, standing_board


def measure_latency(board, target: np.ndarray, cycle_hz: int, samples: int) -> np.ndarray:
    """Latency of `samples` setpoints, s."""
    period = 1.0 / cycle_hz
    sent: dict[int, float] = {}
    on_bus: dict[int, float] = {}

    def note(recs: dict) -> None:
        for seq, t in zip(recs["setpoint_seq"], recs["time_s"]):
            on_bus.setdefault(int(seq), float(t))

    for k in range(samples):
        # Sync to the newest cycle: drop records of cycles already past (noting their setpoints),
        # then the next record is of the first cycle after the previous send.
        note(board.drain_proprioception())
        rec = board.next_proprioception(timeout_s=2 * period)
        assert rec is not None
        note(rec)
        # Send at an offset from that cycle's start spread over the period (before the next
        # cycle starts, so each cycle carries at most one new setpoint).
        start = float(rec["time_s"][-1])
        board.wait(max(0.0, start + period * (k % 10) / 10 - board.now()))
        assert board.now() < start + period, "the cycle's record came after the next cycle start"
        sent[board.send_setpoint(target)] = board.now()
    board.wait(3 * period)
    note(board.drain_proprioception())
    missing = [s for s in sent if s not in on_bus]
    assert not missing, f"setpoints never applied: {missing}"
    return np.array([on_bus[s] - sent[s] for s in sent])


# 140 Hz: a rate whose cycle fits 1 Mbit/s with 10 % spare (conftest.bus_baud), the virtual servos'
# baud (200 Hz needs 2 Mbit/s, which servos take only through `dbot dxl setup`); its period is not a
# whole number of microseconds (7142.9 us), which once hung the virtual robot's wait (see
# board's robot_link::a_wait_to_a_deadline_between_two_microseconds_returns_at_the_next_one).
@pytest.mark.parametrize("cycle_hz", [100, 140])
def test_setpoint_reaches_the_bus_within_two_cycles(tripod_plan, model, cycle_hz: int) -> None:
    board = standing_board(tripod_plan, cycle_hz=cycle_hz)
    board.enter_streaming(timeout_cycles=20)
    # The latency bound is in bus cycles of the requested rate, so the board must keep that rate:
    # a cycle (Sync Write of 22 goals + Sync Read of 22 replies) must fit in the period.
    board.drain_proprioception()
    board.wait(10 / cycle_hz)
    starts = board.drain_proprioception()["time_s"]
    # The board's period is whole microseconds, 1e6 // Hz (7142 us at 140 Hz: 140.02 Hz).
    assert np.allclose(np.diff(starts), (1_000_000 // cycle_hz) * 1e-6, rtol=0, atol=1e-9), (
        f"the bus loop does not keep {cycle_hz} Hz: cycles start {np.diff(starts)} s apart"
    )
    lat = measure_latency(board, servo_rest(tripod_plan, model), cycle_hz, samples=50)
    period = 1.0 / cycle_hz
    print(
        f"\nlatency at {cycle_hz} Hz (simulated clock): min {lat.min() * 1e3:.2f} ms, "
        f"mean {lat.mean() * 1e3:.2f} ms, max {lat.max() * 1e3:.2f} ms "
        f"({lat.max() / period:.2f} cycles)"
    )
    assert np.all(lat >= 0), "a setpoint on the bus before it was sent"
    assert lat.max() <= 2 * period


@pytest.mark.skipif(
    not os.environ.get("DBOT_TEST_PORT"),
    reason="opt-in: runs on a real board only, set DBOT_TEST_PORT=/dev/ttyACM0",
)
# 140 Hz: as above.
@pytest.mark.parametrize("cycle_hz", [100, 140])
def test_latency_on_a_port_within_two_cycles(tripod_plan, model, cycle_hz: int) -> None:
    """On a board or the emulator the host's clock is not the board's, so latency is bounded
    from above on the board's clock: from the start of the last cycle the host had seen when it
    sent (an earlier moment than the send) to the start of the cycle that carried the setpoint."""
    board = standing_board(tripod_plan, cycle_hz=cycle_hz, port=os.environ["DBOT_TEST_PORT"])
    board.enter_streaming(timeout_cycles=20)
    target = servo_rest(tripod_plan, model)
    seen_before: dict[int, int] = {}
    applied: dict[int, int] = {}
    last_seen = None
    for _ in range(50):
        rec = board.next_proprioception(timeout_s=1.0)
        assert rec is not None
        for seq, t in zip(rec["setpoint_seq"], rec["time_us"]):
            applied.setdefault(int(seq), int(t))
        last_seen = int(rec["time_us"][-1])
        seen_before[board.send_setpoint(target)] = last_seen
    board.wait(0.1)
    recs = board.drain_proprioception()
    for seq, t in zip(recs["setpoint_seq"], recs["time_us"]):
        applied.setdefault(int(seq), int(t))
    # A record from before our first setpoint can echo an earlier session's number: skip those.
    lat = (
        np.array([applied[s] - seen_before[s] for s in seen_before if applied.get(s, -1) >= seen_before[s]])
        * 1e-6
    )
    assert len(lat) >= 45, "setpoints lost"
    period = 1.0 / cycle_hz
    print(
        f"\nlatency bound at {cycle_hz} Hz on {board.port}: "
        f"median {np.median(lat) * 1e3:.2f} ms, max {lat.max() * 1e3:.2f} ms "
        f"({lat.max() / period:.2f} cycles)"
    )
    # The bound includes the host's reaction after the record it saw, so it exceeds the true
    # latency; 2 us of slack for the board's timer rounding.
    assert lat.max() <= 2 * period + 2e-6

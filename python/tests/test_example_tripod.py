"""The example controller (examples/tripod_cpg.py) walks the virtual robot in closed loop, and
the stance pattern read off the recorded servo angles is a tripod.

Tripod, by its textbook definition (Wilson 1966; paper section 1): legs LF, RM, LH step together,
RF, LM, RH together, the two groups half a cycle apart, and never both groups in swing at once.
The checks use the stance read off the *measured* joint angles (not the controller's own phase),
after the first third of the run (the oscillators start far from a tripod on purpose).
"""

from __future__ import annotations

import pathlib
import sys

import numpy as np
import pytest

import dbot

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples"
sys.path.insert(0, str(EXAMPLES))

import tripod_cpg  # noqa: E402

LEGS = ["LF", "LM", "LH", "RF", "RM", "RH"]
PHASE_TOL = 0.05  # cycles: 6 bus cycles of a 125-cycle step


def circ_dist(a: float, b: float) -> float:
    d = abs(a - b) % 1.0
    return min(d, 1.0 - d)


def assert_tripod(report: dict[str, float]) -> None:
    assert report["both_swing"] <= 0.02, report
    assert report["agree"] >= 0.9, report
    for leg in tripod_cpg.TRIPOD_A:
        assert circ_dist(report[f"phase_{leg}"], 0.0) <= PHASE_TOL, (leg, report)
    for leg in tripod_cpg.TRIPOD_B:
        assert circ_dist(report[f"phase_{leg}"], 0.5) <= PHASE_TOL, (leg, report)


def pattern(phase_of_leg: dict[str, float], duty: float = 0.6, period: int = 100) -> np.ndarray:
    """A hand-made stance pattern [record, leg]: leg stands for `duty` of each cycle from its
    phase on."""
    t = np.arange(10 * period)
    return np.stack(
        [((t / period - phase_of_leg[leg]) % 1.0) < duty for leg in LEGS], axis=1
    )


def test_tripod_report_accepts_a_tripod_and_rejects_other_gaits() -> None:
    tripod = {"LF": 0, "RM": 0, "LH": 0, "RF": 0.5, "LM": 0.5, "RH": 0.5}
    assert_tripod(tripod_cpg.tripod_report(pattern(tripod), LEGS))
    # A tetrapod (thirds, duty 2/3) and a metachronal wave are not tripods.
    tetra = {"LF": 0, "RM": 0, "LM": 1 / 3, "RH": 1 / 3, "LH": 2 / 3, "RF": 2 / 3}
    wave = {"LH": 0, "LM": 1 / 6, "LF": 2 / 6, "RH": 3 / 6, "RM": 4 / 6, "RF": 5 / 6}
    for other in (tetra, wave):
        with pytest.raises(AssertionError):
            assert_tripod(tripod_cpg.tripod_report(pattern(other, duty=2 / 3), LEGS))


def test_example_walks_the_virtual_robot_in_a_tripod(tmp_path) -> None:
    model = dbot.Model.builtin("drosophibot2")
    plan = dbot.plan(model, slices=50)
    board = dbot.Board.open("virtual")
    rec = tripod_cpg.walk(board, model, plan, steps=12, initial_phase=tripod_cpg.INITIAL_PHASE)
    # Walked: every leg lifted off at least 12 times (10 steps after the transient), and the
    # stance read off the servos shows as many touch-downs.
    assert rec["liftoffs"].min() >= 12
    st = rec["stance"]
    touchdowns = (st[1:] & ~st[:-1]).sum(axis=0)
    assert np.all(touchdowns >= 11), touchdowns
    # The board streamed all along: no fault, every record fresh (setpoint age at most 1).
    assert board.status()["fault"] is None
    assert rec["setpoint_age"].max() <= 1
    # The servos followed: the virtual servos are first-order lags (tau = 20 ms, an estimate
    # of an MX-28 at default gains; host/src/robot/servos.rs) that move towards the previous
    # cycle's goal before reporting. The same law, integrated here from the commanded angles,
    # must give the measured angles to within 2 servo ticks (reported positions are whole ticks).
    cmd, pos, t = rec["commanded_rad"], rec["present_rad"], rec["time_s"]
    tau, tick = 0.02, 2 * np.pi / 4096
    expect = np.empty_like(pos)
    expect[0] = pos[0]
    for k in range(1, len(t)):
        a = 1.0 - np.exp(-(t[k] - t[k - 1]) / tau)
        expect[k] = expect[k - 1] + (cmd[k - 1] - expect[k - 1]) * a
    assert np.abs(pos - expect).max() <= 2 * tick
    settled = st[len(st) // 3 :]
    assert_tripod(tripod_cpg.tripod_report(settled, list(plan.legs)))
    # The recording plots.
    png = tmp_path / "tripod.png"
    tripod_cpg.plot(rec, list(plan.legs), model.servo_joint_names, png)
    assert png.stat().st_size > 10_000

"""The physics robot from Python: ``Board.open("physics")`` is the virtual robot's API over a
MuJoCo body (host/physics) with the firmware in the loop.

What the body changes, checked against the plain virtual robot (``Board.open("virtual")``), whose
servos report the planned torque of the slice being played as their load and no load while
standing or streaming (board::robot::PlannedLoads): on the physics robot the loads are the body's.
Standing, the servos carry the 5 kg robot, so loads are not zero; walking, they differ from the
planned torques; and a leg in stance carries more load than the same leg in swing (it holds up the
body; in swing it holds only itself).
"""

from __future__ import annotations

import pathlib
import sys

import numpy as np

import dbot

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples"
sys.path.insert(0, str(EXAMPLES))

import tripod_cpg  # noqa: E402


def play_and_record(port: str, plan: dbot.Plan, steps: int) -> dict[str, np.ndarray]:
    """Uploads `plan` (planned torques as the bias), plays `steps` steps and records them."""
    board = dbot.Board.open(port)
    board.upload_plan(0, plan, name="tripod", torques=True)
    board.set_telemetry(1)
    board.play(0, steps=steps)
    # The start ramp to the first slice comes before the steps: 2.3 s from the physics robot's
    # resting posture, 5.8 s on the virtual robot, whose servos start at their centres (each leg
    # pair lifted in turn, firmware::playback::ramp).
    rec = board.record(steps * plan.period_s + 7.0)
    assert board.status()["fault"] is None
    board.close()
    return rec


def test_physics_robot_walks_with_loads_that_are_not_the_plan(model) -> None:
    plan = dbot.plan(model, slices=50)
    phys = play_and_record("physics", plan, steps=2)
    virt = play_and_record("virtual", plan, steps=2)

    def by_slice(rec: dict[str, np.ndarray]) -> dict[tuple[int, int], np.ndarray]:
        """Load register per (step, slice) of the walk (first record of each slice)."""
        out: dict[tuple[int, int], np.ndarray] = {}
        for i, (st, sl) in enumerate(zip(rec["step"], rec["slice"])):
            if st < 2:
                out.setdefault((int(st), int(sl)), rec["load_raw"][i])
        return out

    p, v = by_slice(phys), by_slice(virt)
    common = sorted(set(p) & set(v))
    # Both walked both steps through (nearly) every slice.
    assert len(common) >= 0.9 * 2 * plan.slices, len(common)
    lp = np.array([p[k] for k in common], dtype=float)
    lv = np.array([v[k] for k in common], dtype=float)
    # The virtual robot's loads are the planned torques (not zero while playing); the body's
    # differ from them by many load-register units (an MX-28's unit is 0.1 % of its stall torque;
    # measured: RMS 89 units against the planned loads' RMS 164, table 1 at 50 slices).
    assert np.abs(lv).max() > 20
    rms = float(np.sqrt(np.mean((lp - lv) ** 2)))
    assert rms > 30, rms
    # ... yet they are loads of the same walk: the same sign where the plan asks for a sizeable
    # torque, in most of those samples.
    big = np.abs(lv) > 50
    assert big.sum() > 100
    assert np.mean(np.sign(lp[big]) == np.sign(lv[big])) > 0.8


def test_physics_robot_carries_its_weight_while_standing() -> None:
    phys = dbot.Board.open("physics")
    virt = dbot.Board.open("virtual")
    model = dbot.Model.builtin("drosophibot2")
    plan = dbot.plan(model, slices=50)
    loads = {}
    for name, board in (("physics", phys), ("virtual", virt)):
        tripod_cpg.stand(board, plan)
        board.enter_streaming(timeout_cycles=50, feedback_every=1)
        first = board.next_proprioception(timeout_s=0.1)
        assert first is not None
        pose = first["present_rad"][0]
        recs = []
        for _ in range(50):
            board.send_setpoint(pose)
            rec = board.next_proprioception(timeout_s=0.1)
            assert rec is not None
            recs.append(rec["load_raw"][0])
        board.leave_streaming()
        loads[name] = np.array(recs)
    # Virtual: no load in streaming by construction. Physics: the body's weight on the servos.
    assert np.all(loads["virtual"] == 0)
    assert np.abs(loads["physics"]).mean(axis=0).max() > 50, loads["physics"].mean(axis=0)


def test_cpg_example_walks_the_physics_robot(model) -> None:
    plan = dbot.plan(model, slices=50)
    board = dbot.Board.open("physics")
    rec = tripod_cpg.walk(board, model, plan, steps=3, initial_phase=tripod_cpg.INITIAL_PHASE)
    assert rec["liftoffs"].min() >= 3
    assert board.status()["fault"] is None
    assert rec["setpoint_age"].max() <= 1
    # Proprioception carries the body's loads: each leg's servos are more loaded while the leg
    # stands (read off its measured angles) than while it swings, after the start transient.
    legs = tripod_cpg.LegMap(plan, model)
    load = np.array([legs.leg_load(row) for row in rec["load_raw"]])
    st = rec["stance"]
    half = len(st) // 3
    for i, leg in enumerate(plan.legs):
        s, w = st[half:, i], ~st[half:, i]
        assert s.any() and w.any(), leg
        assert load[half:, i][s].mean() > load[half:, i][w].mean(), leg

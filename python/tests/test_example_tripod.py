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
import tomllib

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


MODEL_FILE = pathlib.Path(__file__).resolve().parents[2] / "host" / "planner" / "models" / "drosophibot2.toml"
#: No-load speed at 12 V, rad/s (e-manual datasheets: MX-28 55 rpm, MX-64 63 rpm).
NO_LOAD_RAD_S = {"mx28": 55 * 2 * np.pi / 60, "mx64": 63 * 2 * np.pi / 60}


#: Stall torque at 12 V, N m (e-manual datasheets: MX-28 2.5 N m, MX-64 6.0 N m).
STALL_NM = {"mx28": 2.5, "mx64": 6.0}


def servo_joints(model: dbot.Model) -> list[dict]:
    """The model file's joint entries of the servo joints, in joint-map order."""
    with open(MODEL_FILE, "rb") as f:
        joints = {f"{j['leg']}_{j['kind']}": j for j in tomllib.load(f)["joint"]}
    return [joints[name] for name in model.servo_joint_names]


def omega0_of_servo_joints(model: dbot.Model) -> np.ndarray:
    """Each servo joint's no-load speed, rad/s, from its actuator in the model file."""
    return np.array([NO_LOAD_RAD_S[j["actuation"]] for j in servo_joints(model)])


def p_gain_of_servo_joints(model: dbot.Model) -> np.ndarray:
    """The Position P Gain the firmware writes for each servo joint at torque-on: the joint's
    stiffness in the e-manual's P units, k = P / 128 / 885 * stall torque * 4096 / 2 pi, rounded
    (993 for every joint of Drosophibot II: 14.29 N m/rad on the MX-28s, 34.29 on the MX-64s)."""
    return np.array(
        [
            round(
                j["stiffness_nm_per_rad"]
                / (STALL_NM[j["actuation"]] / 128 / 885 * 4096 / (2 * np.pi))
            )
            for j in servo_joints(model)
        ]
    )


def servo_law(
    cmd: np.ndarray, t: np.ndarray, start: np.ndarray, omega0: np.ndarray, p_gain: np.ndarray
) -> np.ndarray:
    """Present angles [record, joint] the virtual servos must report, rad.

    The servo (dynamixel/src/sim/physics.rs, after the MX e-manual's P controller): PWM duty
    d = clamp(P / 128 * error_ticks / 885, -1, 1) at the joint's P gain (`p_gain_of_servo_joints`;
    at 993: 5.71 / rad), and with no external load (none while streaming) the quasi-static motor
    turns at omega = omega0 * d: a first-order lag of time constant 1 / (omega0 * 5.71 / rad),
    30.4 ms (MX-28) or 26.5 ms (MX-64), that saturates at the no-load speed for errors beyond
    0.175 rad. In the wire's direction convention the
    error is goal minus present in joint radians (a joint's sign flips both alike).

    Timing on the simulated 1 Mbit/s wire (10 us a byte): a cycle starts with the Sync Write of
    the goals, 14 + 5 n bytes, and the servos take the new goal when it ends; the Sync Read of
    14 + n bytes follows, and every servo samples its present position when that ends (its
    reply is computed then). So between two reads a servo heads for the previous goal until
    (14 + n) * 10 us before the read, then for the new one.

    Tolerance (2 ticks): reported positions are whole ticks (half a tick), the start is a
    reported position (half a tick, decaying), and the simulator's Euler steps of 1 ms against
    this finer integration (well under 0.1 tick).
    """
    n = cmd.shape[1]
    new_goal_s = (14 + n) * 10e-6
    k_per_rad = (p_gain / 128) / 885 / (2 * np.pi / 4096)
    h_max = 1e-4

    def run(x: np.ndarray, goal: np.ndarray, dt: float) -> np.ndarray:
        steps = max(1, int(np.ceil(dt / h_max)))
        h = dt / steps
        for _ in range(steps):
            x = x + h * omega0 * np.clip(k_per_rad * (goal - x), -1.0, 1.0)
        return x

    expect = np.empty_like(cmd)
    expect[0] = start
    for k in range(1, len(t)):
        x = run(expect[k - 1], cmd[k - 1], t[k] - t[k - 1] - new_goal_s)
        expect[k] = run(x, cmd[k], new_goal_s)
    return expect


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
    # The servos followed: the servo law, integrated here from the commanded angles, must give
    # the measured angles to within 2 servo ticks (see `servo_law`).
    cmd, pos, t = rec["commanded_rad"], rec["present_rad"], rec["time_s"]
    expect = servo_law(
        cmd, t, pos[0], omega0_of_servo_joints(model), p_gain_of_servo_joints(model)
    )
    tick = 2 * np.pi / 4096
    assert np.abs(pos - expect).max() <= 2 * tick
    settled = st[len(st) // 3 :]
    assert_tripod(tripod_cpg.tripod_report(settled, list(plan.legs)))
    # The recording plots.
    png = tmp_path / "tripod.png"
    tripod_cpg.plot(rec, list(plan.legs), model.servo_joint_names, png)
    assert png.stat().st_size > 10_000

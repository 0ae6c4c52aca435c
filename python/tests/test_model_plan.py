"""Models and planning through the bindings: shapes, units and laws the plan must obey."""

from __future__ import annotations

import math

import numpy as np
import pytest

import dbot


def test_builtin_models_listed_and_loadable() -> None:
    assert set(dbot.BUILTIN_MODELS) == {"drosophibot2", "scale-drosophila"}
    m = dbot.Model.builtin("drosophibot2")
    # The robot has 22 servos (paper section 2.4) and six legs.
    assert len(m.servo_joint_names) == 22
    assert sorted(m.legs) == sorted(["LF", "LM", "LH", "RF", "RM", "RH"])
    lim = m.limits
    assert lim.shape == (len(m.joint_names), 2)
    assert np.all(lim[:, 0] <= lim[:, 1])


def test_unknown_model_names_the_known_ones() -> None:
    with pytest.raises(ValueError, match="drosophibot2"):
        dbot.Model.builtin("no-such-robot")


def test_model_file_that_does_not_exist_is_a_clear_error(tmp_path) -> None:
    with pytest.raises(ValueError, match="missing.toml"):
        dbot.Model.load(tmp_path / "missing.toml")


def test_plan_arrays_and_timing(model: dbot.Model) -> None:
    p = dbot.plan(model, slices=40, swing_s=0.5, duty=0.6)
    n_j = len(model.joint_names)
    assert p.angles.shape == (40, n_j)
    assert p.velocities.shape == (40, n_j)
    assert p.stance.shape == (40, 6)
    assert p.feet.shape == (40, 6, 3)
    # T = T_sw / (1 - duty) (paper, table 1 definitions): 0.5 / 0.4 = 1.25 s.
    assert math.isclose(p.period_s, 1.25, rel_tol=1e-12)
    assert math.isclose(p.dt, 1.25 / 40, rel_tol=1e-12)
    # Each leg stands for `duty` of the cycle: 0.6 * 40 = 24 slices (one slice of rounding).
    assert np.all(np.abs(p.stance.sum(axis=0) - 24) <= 1)


def test_default_preset_is_the_clis_servo_safe() -> None:
    """`dbot.plan(model)` starts from the same preset as `dbot plan` (servo-safe), not table 1's
    0.5 s swing that the front servos cannot follow."""
    robot = dbot.Model.builtin("drosophibot2")
    # servo-safe on Drosophibot II: table 1 at a 1.0 s swing, duty 0.6: T = 1.0 / 0.4 = 2.5 s.
    p = dbot.plan(robot, slices=40)
    assert math.isclose(p.period_s, 2.5, rel_tol=1e-12)
    assert math.isclose(p.duty, 0.6, rel_tol=1e-12)
    # Naming the preset gives the same plan; table1 is the original solver's 0.5 / 0.4 = 1.25 s.
    named = dbot.plan(robot, preset="servo-safe", slices=40)
    assert math.isclose(named.period_s, p.period_s, rel_tol=0) and np.array_equal(
        named.angles, p.angles
    )
    assert math.isclose(dbot.plan(robot, preset="table1", slices=40).period_s, 1.25, rel_tol=1e-12)
    # Keyword arguments still override the preset: 1.6 s swing -> 4 s period.
    assert math.isclose(dbot.plan(robot, swing_s=1.6, slices=40).period_s, 4.0, rel_tol=1e-12)
    # The fly's actuators are not servos: servo-safe keeps its table 1 swing, 0.1 / 0.4 = 0.25 s.
    fly = dbot.plan(dbot.Model.builtin("scale-drosophila"), slices=40)
    assert math.isclose(fly.period_s, 0.25, rel_tol=1e-12)


def test_unknown_preset_names_the_known_ones(model: dbot.Model) -> None:
    with pytest.raises(ValueError, match="no-such-preset.*servo-safe, table1"):
        dbot.plan(model, preset="no-such-preset")


def test_plan_velocities_are_derivatives_of_angles(model: dbot.Model) -> None:
    p = dbot.plan(model, slices=60)
    # Periodic central difference by hand, independent of the planner's own routine.
    q = p.angles
    by_hand = (np.roll(q, -1, axis=0) - np.roll(q, 1, axis=0)) / (2 * p.dt)
    assert np.allclose(p.velocities, by_hand, atol=1e-9)


def test_tripod_plan_has_antiphase_groups(model: dbot.Model) -> None:
    p = dbot.plan(model, slices=50)
    idx = {leg: i for i, leg in enumerate(p.legs)}
    st = p.stance
    for a, b in [("LF", "RM"), ("RM", "LH"), ("RF", "LM"), ("LM", "RH")]:
        assert np.array_equal(st[:, idx[a]], st[:, idx[b]]), (a, b)
    # The two tripods never swing together.
    swing_a = ~st[:, idx["LF"]]
    swing_b = ~st[:, idx["RF"]]
    assert not np.any(swing_a & swing_b)


def test_bad_parameters_name_the_field(model: dbot.Model) -> None:
    with pytest.raises(ValueError, match="duty"):
        dbot.plan(model, duty=1.5)
    with pytest.raises(ValueError, match="no_such_field"):
        dbot.plan(model, no_such_field=1.0)
    with pytest.raises(ValueError, match="slices"):
        dbot.plan(model, slices="many")


def test_step_table_bytes_start_with_the_format_magic(tripod_plan: dbot.Plan) -> None:
    table = tripod_plan.step_table("tripod")
    # protocol/src/gait: magic "DBGT", then the format version.
    assert table[:4] == b"DBGT"
    with pytest.raises(ValueError, match="16"):
        tripod_plan.step_table("a-name-that-is-far-too-long-for-the-table")

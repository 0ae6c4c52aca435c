"""Curves through the bindings: ``dbot.plan(model, turn_deg=, radius_m=)`` plans what the CLI's
``--turn/--radius`` plans (the same rule, planner::gait::Turn), checked by the ground's motion."""

from __future__ import annotations

import math

import numpy as np
import pytest

import dbot


@pytest.fixture(scope="module")
def robot() -> dbot.Model:
    return dbot.Model.builtin("drosophibot2")


def stance_distances(p: dbot.Plan, centre: tuple[float, float]) -> list[np.ndarray]:
    """Per leg, the horizontal distance of the stance foot from `centre` (thorax frame) over its
    stance slices."""
    feet, stance = p.feet, p.stance
    c = np.array(centre)
    return [np.linalg.norm(feet[stance[:, i], i, :2] - c, axis=1) for i in range(len(p.legs))]


def test_turn_deg_is_the_rotation_per_stance(robot: dbot.Model) -> None:
    # 10 deg per step at duty 0.6 is 6 deg of rotation per stance.
    a = dbot.plan(robot, slices=40, turn_deg=10.0)
    b = dbot.plan(robot, slices=40, rotation_rad=math.radians(6.0))
    np.testing.assert_allclose(a.angles, b.angles, atol=1e-12)


def test_stance_feet_ride_on_circles_about_the_turning_centre(robot: dbot.Model) -> None:
    # On a 0.5 m left radius the ground turns about (0, 0.5) in the thorax frame: every stance
    # foot keeps its distance from that point; on the spot, from the thorax origin.
    for kwargs, centre in [
        ({"radius_m": 0.5}, (0.0, 0.5)),
        ({"turn_deg": -20.0, "radius_m": 0.0}, (0.0, 0.0)),
    ]:
        p = dbot.plan(robot, slices=60, **kwargs)
        for d in stance_distances(p, centre):
            assert d.size > 0
            assert np.ptp(d) < 1e-9, (kwargs, d)


def test_nonsense_turns_name_the_parameter(robot: dbot.Model) -> None:
    with pytest.raises(ValueError, match="turn_deg.*-180 and 180"):
        dbot.plan(robot, turn_deg=190.0)
    with pytest.raises(ValueError, match="radius_m.*on the spot"):
        dbot.plan(robot, radius_m=0.0)

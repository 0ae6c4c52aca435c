"""The perturbation platform's servo in `Board.record`'s telemetry: with a platform set up (the
physics robot answers the lab's platform servo, ID 22) every record that carries it has its goal,
which at rest is the lab's rest position (2020 ticks, ../shared/reference/lab-practice.md), and
its present position; without a platform the keys are absent."""

from __future__ import annotations

import numpy as np

import dbot

REST_TICKS = 2020


def test_the_platform_servo_is_in_the_telemetry_only_while_set_up() -> None:
    with dbot.Board.open("physics") as b:
        setup = b.set_platform("RM:1:rise", steps=2, platform_id=22)
        assert setup["rest"] == REST_TICKS
        r = b.record(0.2)
        goal, present = r["platform_goal_ticks"], r["platform_present_ticks"]
        assert goal.shape == present.shape == r["time_s"].shape
        carried = ~np.isnan(goal)
        # 0.2 s at 100 Hz: most records come after the setup took effect.
        assert carried.sum() >= 10
        assert np.all(goal[carried] == REST_TICKS)
        assert np.all(np.isnan(present) == ~carried)
        assert np.all((present[carried] >= 0) & (present[carried] <= 4095))
        b.clear_platform()
        r = b.record(0.1)
        assert "platform_goal_ticks" not in r and "platform_present_ticks" not in r

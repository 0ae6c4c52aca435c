"""`DbotEnv.step`'s native path on the physics robot (`dbot._native.EnvStepper`, taken with the
default reward) against its general path (each part in Python over `Board.stream_step`, taken
with any other reward function): the reference is the general path, made to run by a reward
that is `forward_progress` under another name. Two environments, each its own physics robot,
stepped with the same actions must return the same values bit for bit: every observation array,
the reward, both flags and every `info` value (the body's arrays included), including actions
outside the joint limits (clipped), torques in the action, several bus cycles a step, a plan's
predicted strain and a fall. A wrong length is refused by name on both.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import dbot
from dbot.env import DbotEnv, forward_progress


def general_reward(*args: Any) -> float:
    """`forward_progress` under another name: `DbotEnv.step` takes its general path."""
    return forward_progress(*args)


def assert_same(a: Any, b: Any, where: str) -> None:
    """`a` and `b` equal bit for bit: dicts key for key in the same order, arrays byte for byte
    with dtype and shape."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and list(a) == list(b), (where, list(a), list(b))
        for k in a:
            assert_same(a[k], b[k], f"{where}[{k!r}]")
    elif isinstance(a, np.ndarray):
        assert isinstance(b, np.ndarray), where
        assert (a.dtype, a.shape) == (b.dtype, b.shape), where
        assert a.tobytes() == b.tobytes(), where
    else:
        assert type(a) is type(b) and (a == b or (a != a and b != b)), (where, a, b)


def pair(**kw: Any) -> tuple[DbotEnv, DbotEnv]:
    fast = DbotEnv("physics", **kw)
    general = DbotEnv("physics", reward=general_reward, **kw)
    for env in (fast, general):
        env.reset(seed=0)
    assert fast._fast is not None  # the native path is the one under test
    return fast, general


def step_both(fast: DbotEnv, general: DbotEnv, actions: list[Any]) -> list[bool]:
    """Steps both with each action; asserts every return the same; the terminated flags."""
    ended = []
    for i, a in enumerate(actions):
        got = fast.step(a)
        want = general.step(a)
        assert len(got) == len(want) == 5
        for name, x, y in zip(("obs", "reward", "terminated", "truncated", "info"), got, want):
            assert_same(x, y, f"step {i} {name}")
        ended.append(got[2])
    return ended


def test_the_native_step_returns_what_the_general_step_does() -> None:
    fast, general = pair(max_episode_steps=30)
    rng = np.random.default_rng(3)
    rest = fast.rest_rad
    low, high = fast.action_space.low, fast.action_space.high
    actions: list[Any] = [rest + rng.normal(0.0, 0.1, rest.shape) for _ in range(20)]
    # Beyond the limits on both sides (clipped), a list, float32.
    actions += [np.where(np.arange(22) % 2 == 0, low - 1.0, high + 1.0) for _ in range(3)]
    actions += [list(rest), (rest + 0.05).astype(np.float32)]
    actions += [rest] * 5
    ended = step_both(fast, general, actions)
    assert fast._steps == 30 and not any(ended)
    for env in (fast, general):
        env.close()


def test_torques_several_cycles_and_a_plans_strain_take_the_same_values() -> None:
    gait = dbot.plan(dbot.Model.builtin("drosophibot2"), slices=20)
    fast, general = pair(max_episode_steps=12, torques=True, cycles_per_step=3, gait=gait)
    rng = np.random.default_rng(4)
    rest = fast.rest_rad
    actions = [
        {
            "angles_rad": rest + rng.normal(0.0, 0.1, rest.shape),
            # Some beyond the stall torque (clipped).
            "torques_nm": rng.normal(0.0, 3.0, rest.shape),
        }
        for _ in range(12)
    ]
    step_both(fast, general, actions)
    assert "predicted_strain_microstrain" in fast._info
    for env in (fast, general):
        env.close()


def test_a_fall_ends_both_at_the_same_step() -> None:
    # A fraction of 2: the standing robot is below twice its start height, a fall at once.
    fast, general = pair(max_episode_steps=5, fall_height_fraction=2.0)
    assert step_both(fast, general, [fast.rest_rad]) == [True]
    for env in (fast, general):
        env.close()


def test_a_wrong_length_is_refused_by_name_and_nothing_is_sent() -> None:
    fast, general = pair(max_episode_steps=5)
    with pytest.raises(ValueError, match="angles_rad: 21 values; give one per servo joint"):
        fast.step(fast.rest_rad[:21])
    with pytest.raises(ValueError):
        general.step(general.rest_rad[:21])
    # Neither counted a step nor moved: the next steps agree.
    step_both(fast, general, [fast.rest_rad] * 3)
    for env in (fast, general):
        env.close()

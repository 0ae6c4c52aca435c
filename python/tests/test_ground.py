"""The ground is one typed value parsed in one place (`planner::terrain::Ground`), so every door
says the same: `dbot plan --terrain`, `dbot.plan(terrain=)`, `Board.open("physics:SCENE")` and
the environment's scene option refuse the same text with the same words; the planner refuses
uneven ground it cannot plan for, naming the scene to walk the plan on instead.
"""

from __future__ import annotations

import pytest

import dbot
from dbot.env import DbotEnv
from dbot_cli import refused

REFUSAL = (
    "terrain `blocks:4:0.01:0.05:0`: the planner plans for flat, incline and the held ball only; "
    "uneven ground (blocks) is a scene of the physics robot: plan for flat and walk the plan on "
    "`physics:blocks:4:0.01:0.05:0`"
)
UNKNOWN = "terrain `lava`: unknown terrain `lava` (expected flat, incline:DEG,"


def assert_plan_refuses(terrain: str, words: str, tmp_path) -> None:
    """`dbot.plan` and `dbot plan` both refuse `terrain`, in words that hold `words`."""
    model = dbot.Model.builtin("drosophibot2")
    with pytest.raises(ValueError) as e:
        dbot.plan(model, terrain=terrain)
    assert words in str(e.value)
    assert words in refused("plan", "--terrain", terrain, "--out", "p", cwd=tmp_path)


def test_the_planner_refuses_blocks_in_the_same_words_from_the_cli_and_python(tmp_path) -> None:
    assert_plan_refuses("blocks:4", REFUSAL, tmp_path)


def test_an_unknown_ground_is_refused_alike_everywhere(tmp_path) -> None:
    assert_plan_refuses("lava", UNKNOWN, tmp_path)
    with pytest.raises(dbot.BoardError) as e:
        dbot.Board.open("physics:lava")
    assert str(e.value).startswith("port `physics:lava`: " + UNKNOWN)
    env = DbotEnv("physics", max_episode_steps=5)
    with pytest.raises(dbot.BoardError) as e:
        env.reset(options={"scene": "lava"})
    assert UNKNOWN in str(e.value)


def test_the_planner_plans_for_its_own_terrains() -> None:
    model = dbot.Model.builtin("drosophibot2")
    for terrain in ("flat", "incline:10", "ball"):
        assert dbot.plan(model, terrain=terrain, slices=20).slices == 20

"""The learning example (python/examples/learn_residual.py), a smoke run: CMA-ES trains a couple
of generations of residual joint targets on `dbot.env.VectorEnv`, saves the policy, the
optimiser and the learning curve, reloads them and resumes. It checks the pipeline, not that it
converges (the full run's curve is in docs/performance.md):

* the residual of all-zero parameters is zero (the policy is the open-loop planned gait), and it
  never exceeds its bound (tanh x 0.15 rad);
* the saved policy reloads to the same parameters, and walking them again gives the reward saved
  with them (the physics robot is deterministic);
* the curve has one point per generation, its steps counted by hand (episode x popsize per
  generation after the open-loop rollout's episode), and training resumes from the saved state.
"""

from __future__ import annotations

import importlib.util
import pathlib
import sys

import numpy as np
import pytest

from dbot.env import VectorEnv

EXAMPLE = pathlib.Path(__file__).resolve().parents[1] / "examples" / "learn_residual.py"


@pytest.fixture(scope="module")
def learn():
    spec = importlib.util.spec_from_file_location("learn_residual", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    assert spec.loader is not None
    # Registered before it runs: its dataclass looks its module up by name.
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


def test_zero_parameters_are_the_planned_gait_and_the_residual_is_bounded(learn) -> None:
    for phase in (0.0, 0.3, 0.9):
        assert np.all(learn.residual(np.zeros(66), phase) == 0.0)
    big = np.full(66, 100.0)
    assert np.all(np.abs(learn.residual(big, 0.1)) <= learn.SCALE_RAD)


def test_trains_saves_reloads_and_resumes(learn, tmp_path) -> None:
    steps, popsize = 30, 4
    curve = learn.train(tmp_path, envs=2, generations=2, popsize=popsize, episode_steps=steps)
    assert (tmp_path / "learning_curve.png").stat().st_size > 0
    # The open-loop rollout's episode, then popsize episodes per generation.
    assert list(curve["steps"]) == [steps + popsize * steps, steps + 2 * popsize * steps]
    saved = learn.load(tmp_path / "policy.npz")
    assert np.array_equal(saved["theta"], curve["theta"])
    # Walking the saved parameters again gives the reward saved with them.
    env = VectorEnv(1, max_episode_steps=steps, torques=True)
    again = learn.rollouts(env, saved["theta"][None], steps)
    env.close()
    assert again[0] == float(saved["reward"])
    resumed = learn.train(tmp_path, envs=2, generations=1, popsize=popsize, episode_steps=steps,
                          resume=True)
    assert list(resumed["steps"])[-1] == steps + 3 * popsize * steps

"""`dbot.env.VectorEnv`, N physics robots stepped on Rust threads:

* each sub-environment passes Gymnasium's own conformance checker (`check_env`, an external
  reference) as a plain environment (`dbot.vector_env.SubEnv`: the same Rust core, one robot);
* it equals Gymnasium's `SyncVectorEnv` over the single `DbotEnv` (the independent truth: the
  Python environment driving `dbot.Board`), observation, reward and flags bit for bit, through a
  next-step autoreset;
* results are bit-identical for 1 and 2 worker threads and on the calling thread (`threads=0`),
  and `gymnasium.make_vec` builds it; by default a thread per robot up to the CPU count, and
  one robot on the calling thread;
* a reset from the stored settled state (a cheap reset) gives the same episode, bit for bit, as
  a reset that simulates the settling again;
* actions beyond the action space's bounds step as the same actions clipped by `np.clip` (the
  Rust core clips them);
* ``scene="SCENE+model:FILE"`` runs that file's body (Hooke's law against the built-in one), and
  a file that cannot be read is refused when the environment is made, named.
"""

from __future__ import annotations

import os
import pathlib

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from gymnasium.vector import AutoresetMode, SyncVectorEnv

from dbot.env import DbotEnv, VectorEnv
from dbot.vector_env import ENV_ID, SubEnv

#: Steps per episode: short, so that an autoreset comes within a few steps.
EPISODE = 3


def actions(rest: np.ndarray, steps: int) -> list[np.ndarray]:
    """Seeded joint targets around the resting posture, one row per sub-environment."""
    rng = np.random.default_rng(7)
    return [rest + rng.normal(0.0, 0.05, rest.shape) for _ in range(steps)]


def test_each_sub_environment_passes_check_env() -> None:
    env = SubEnv(max_episode_steps=20)
    check_env(env, skip_render_check=True)
    env.close()


def test_equals_sync_vector_env_over_dbot_env_through_an_autoreset() -> None:
    n = 2
    vec = VectorEnv(n, threads=2, max_episode_steps=EPISODE)
    sync = SyncVectorEnv(
        [lambda: DbotEnv("physics", max_episode_steps=EPISODE) for _ in range(n)],
        autoreset_mode=AutoresetMode.NEXT_STEP,
    )
    assert vec.metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP
    a, ai = vec.reset(seed=1)
    b, bi = sync.reset(seed=1)
    for key in b:
        assert a[key].tobytes() == b[key].tobytes(), key
    assert np.array_equal(ai["time_s"], bi["time_s"])
    autoresets = 0
    ended = np.zeros(n, dtype=bool)
    for act in actions(vec.rest_rad, EPISODE + 3):
        a, ar, at, atr, ai = vec.step(act)
        b, br, bt, btr, bi = sync.step(act)
        for key in b:
            assert a[key].tobytes() == b[key].tobytes(), key
        assert ar.tobytes() == br.tobytes()
        assert np.array_equal(at, bt) and np.array_equal(atr, btr)
        assert np.array_equal(ai["time_s"], bi["time_s"])
        assert ai["body"]["thorax_position_m"].tobytes() == bi["body"]["thorax_position_m"].tobytes()
        # The step after truncation resets: reward 0, both flags False (next-step autoreset),
        # the robot back at its reset clock.
        if ended.any():
            autoresets += 1
            assert np.all(ar[ended] == 0.0) and not at[ended].any() and not atr[ended].any()
        ended = at | atr
    assert autoresets == 1
    vec.close()
    sync.close()


def test_identical_for_any_thread_count_and_made_by_make_vec() -> None:
    runs = []
    for threads in (0, 1, 2):
        env = VectorEnv(2, threads=threads, max_episode_steps=EPISODE)
        assert env.threads == threads
        obs, _ = env.reset(seed=3)
        trace = [obs]
        for act in actions(env.rest_rad, EPISODE + 2):
            obs, reward, terminated, truncated, _ = env.step(act)
            trace.append({**obs, "reward": reward, "done": terminated | truncated})
        runs.append(trace)
        env.close()
    for other in runs[1:]:
        for a, b in zip(runs[0], other, strict=True):
            for key in a:
                assert a[key].tobytes() == b[key].tobytes(), key
    made = gym.make_vec(ENV_ID, num_envs=3)
    assert isinstance(made.unwrapped, VectorEnv) and made.num_envs == 3
    # The default: a thread per robot up to the CPU count; one robot on the calling thread.
    assert made.unwrapped.threads == min(3, os.cpu_count() or 1)
    one = VectorEnv(1)
    assert one.threads == 0
    one.close()
    assert made.observation_space["present_rad"].shape == (3, 22)
    made.close()


def test_a_reset_from_the_stored_settled_state_equals_simulating_the_settling() -> None:
    def episodes(cheap: bool) -> tuple[list, list[bool]]:
        env = VectorEnv(1, threads=1, cheap_reset=cheap)
        traces, skipped = [], []
        for _ in range(2):
            obs, info = env.reset()
            skipped.append(bool(info["settle_skipped"][0]))
            trace = [{**obs, "x": info["body"]["thorax_position_m"]}]
            for act in actions(env.rest_rad, 20):
                obs, reward, _, _, info = env.step(act)
                trace.append({**obs, "x": info["body"]["thorax_position_m"], "r": reward})
            traces.append(trace)
        env.close()
        return traces, skipped

    full, full_skipped = episodes(cheap=False)
    cheap, cheap_skipped = episodes(cheap=True)
    # The first reset simulates the settling either way; the second skips it when allowed.
    assert full_skipped == [False, False] and cheap_skipped == [False, True]
    for a, b in zip(full[1], cheap[1], strict=True):
        for key in a:
            assert a[key].tobytes() == b[key].tobytes(), key


def test_an_action_of_the_wrong_shape_is_refused_by_name() -> None:
    env = VectorEnv(2, threads=1)
    with pytest.raises(ValueError, match=r"actions: shape \(22,\), give \(2, 22\)"):
        env.step(np.zeros(22))
    env.close()


def test_the_robots_take_dbot_envs_settings_and_refuse_its_reward_and_drawing() -> None:
    # DbotEnv's keywords reach each robot (its episode ends at DbotEnv's max_episode_steps);
    # a reward function and a render mode are DbotEnv's alone.
    env = VectorEnv(1, threads=0, max_episode_steps=2, fall_tilt_rad=1.0)
    assert env._single.fall_tilt_rad == 1.0
    env.reset(seed=0)
    truncated = [env.step(np.asarray([env.rest_rad[0]]))[3][0] for _ in range(2)]
    assert truncated == [False, True]
    env.close()
    for fixed in ("reward", "render_mode"):
        with pytest.raises(TypeError, match=f"VectorEnv takes no '{fixed}'"):
            VectorEnv(1, **{fixed: None})
    with pytest.raises(TypeError, match="settle"):
        VectorEnv(1, settle=0.1)


def test_actions_beyond_the_bounds_are_clipped_as_np_clip_clips_them() -> None:
    # Targets 4 rad beyond the joint limits (beyond what a setpoint can carry, +-3.2767 rad:
    # unclipped, the step fails) and torques of 10 N m (unclipped, the firmware's torque bias
    # would differ), both ways, give the very steps of the same actions clipped by NumPy (the
    # core clips them in Rust now).
    runs = []
    for clip_here in (False, True):
        env = VectorEnv(1, threads=0, torques=True, max_episode_steps=20)
        obs, _ = env.reset(seed=0)
        trace = [obs]
        sign = np.where(np.arange(22) % 2 == 0, 1.0, -1.0)
        for k in range(6):
            up = sign * (-1) ** k > 0
            angles = np.where(up, env._high + 4.0, env._low - 4.0)[None, :]
            torques = 10.0 * sign[None, :] * (-1) ** (k // 2)
            if clip_here:
                angles = np.clip(angles, env._low, env._high)
                torques = np.clip(torques, -env._stall, env._stall)
            obs, reward, *_ = env.step({"angles_rad": angles, "torques_nm": torques})
            trace.append({**obs, "reward": reward})
        env.close()
        runs.append(trace)
    moved = runs[1][-1]["present_rad"] - runs[1][0]["present_rad"]
    assert np.abs(moved).max() > 0.05  # the clipped targets moved the joints
    for a, b in zip(*runs, strict=True):
        for key in a:
            assert a[key].tobytes() == b[key].tobytes(), key


def test_a_scene_naming_a_model_file_runs_that_files_body(tmp_path) -> None:
    # ``scene="SCENE+model:FILE"`` (docs/usage.md) runs the body of a model file, as DbotEnv's
    # port does (test_env.py's Hooke's-law test: every servo's P gain divisor doubled, so the
    # joints deflect about twice as far standing under the same weight); a missing file is
    # refused naming it.
    root = pathlib.Path(__file__).resolve().parents[2]
    text = (root / "host/planner/models/drosophibot2.toml").read_text()
    soft = tmp_path / "soft.toml"
    soft.write_text(text.replace("p_gain_divisor = 128.0", "p_gain_divisor = 256.0"))

    def standing_deflection(scene: str) -> float:
        env = VectorEnv(1, threads=0, scene=scene, max_episode_steps=60)
        obs, _ = env.reset(seed=0)
        for _ in range(50):
            obs, _, terminated, _, _ = env.step(np.asarray([env.rest_rad[0]]))
            assert not terminated[0], scene
        env.close()
        return float(np.sum(np.abs(obs["present_rad"][0] - env.rest_rad[0])))

    builtin = standing_deflection("flat+floor")
    fitted = standing_deflection(f"flat+floor+model:{soft}")
    assert 1.6 * builtin < fitted < 2.5 * builtin, (builtin, fitted)
    missing = tmp_path / "missing.toml"
    with pytest.raises(ValueError, match=f"model file {missing}: {missing}: cannot read"):
        VectorEnv(1, threads=0, scene=f"flat+model:{missing}")

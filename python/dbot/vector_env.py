"""Many physics robots at once: :class:`VectorEnv`, a ``gymnasium.vector.VectorEnv`` of N
:class:`dbot.env.DbotEnv` robots on ``physics:SCENE`` (re-exported as ``dbot.env.VectorEnv``).

Each sub-environment is a physics robot with the firmware in the loop, reset and stepped exactly as
``DbotEnv`` does it (the same requests on the board link in the same order, in Rust:
python/src/vector_sub.rs), so sub-environment ``i`` equals ``DbotEnv`` bit for bit. The N robots
step on ``threads`` Rust worker threads with the GIL released (python/src/vector.rs); robot ``i``
lives on thread ``i % threads`` and shares nothing with the others, so results are identical
whatever the thread count. ``threads=0`` steps them on the calling thread instead, the GIL held
(no hand-over of each step to a worker: the cheapest for one robot, or for a process that
parallelises otherwise, e.g. a process pool or Ray actors); default: the calling thread for one
robot (a worker would only add the hand-over, about 4 % of a step: docs/performance.md), one
thread per robot up to the CPU count for more. Either way a ``VectorEnv`` stays on the Python
thread that made it (its Rust core is one ``unsendable`` class, as the robots of ``threads=0``
must be): a call from another thread raises ``PanicException`` ("... is unsendable, but sent to
another thread").

Spaces: ``single_observation_space`` and ``single_action_space`` are ``DbotEnv``'s (the ``Dict``
observation with the strain gauges; the 22 joint targets, or with ``torques=True`` the ``Dict``
of targets and torque feed-forward); the batched spaces have N rows.

Autoreset: Gymnasium 1.x's next-step mode (``AutoresetMode.NEXT_STEP``, the default): the step
after a sub-environment terminated or truncated resets it, ignores its action, and returns its
first observation with reward 0 and both flags False. ``reset(seed=s)`` seeds sub-environment
``i`` with ``s + i`` (a list gives one seed each): each sub-environment's ``np_random`` and
action space. The physics robot itself is deterministic (its one random stream, the Present Load
noise, has a fixed seed), so the seed changes nothing the robots do. Reset options: ``scene``
(kept for later resets) and ``stiffness_nm_rad`` (this episode's), for every reset sub-
environment, and ``reset_mask`` (N booleans: reset only those).

Cheap resets (``cheap_reset=True``, the default): a reset opens a fresh robot and sends
``DbotEnv``'s requests, but the settling after torque on (the gravity ramp's 1 s and
``settle_s``), simulated in full at a sub-environment's first reset of a scene and stiffness, is
afterwards skipped: the body stands still (MuJoCo is not stepped) while the firmware's bus cycles
pass, then becomes the settled state stored at that first reset, two bus cycles before the
settling's end (``physics::PhysicsRobot::skip_to_state``: MuJoCo's data in full, the servos'
control-law memory, the gauges' recent samples, the load noise generator). The episode that
follows is bit-identical to one after a full reset (python/tests/test_vector_env.py);
``info["settle_skipped"]`` says which reset a sub-environment had. Not identical: what the
firmware read from the servos during the skipped span (it holds its posture while standing and
keeps none of it in what the environment observes).

Infos (one dict of arrays, each key with its boolean mask ``_key`` as Gymnasium's vector
environments give them): ``time_s`` (the proprioception clock, s), ``state`` (run state names),
``settle_skipped`` (the last reset was a cheap one) and ``body`` with ``thorax_position_m`` (N x 3) and ``thorax_orientation`` (N x 4, w x y z).

Reward: forward progress (the thorax's world x advance in the step, m), as ``DbotEnv``'s
default; termination and truncation as ``DbotEnv``'s (a firmware fault, a fall by its rule,
``max_episode_steps``).
"""

from __future__ import annotations

import os
from typing import Any, Sequence

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode
from gymnasium.vector import VectorEnv as _GymVectorEnv
from gymnasium.vector.utils import batch_space

from ._native import Model, Plan, VectorCore, VectorOptions

#: The id under which ``gymnasium.make_vec`` builds :class:`VectorEnv` (``dbot.env`` registers it).
ENV_ID = "dbot/Physics-v0"


class VectorEnv(_GymVectorEnv):
    """N Drosophibot II physics robots with their firmware, stepped on Rust threads."""

    metadata = {"autoreset_mode": AutoresetMode.NEXT_STEP, "render_modes": []}

    def __init__(
        self,
        num_envs: int = 2,
        *,
        threads: int | None = None,
        scene: str = "flat",
        cheap_reset: bool = True,
        **robot: Any,
    ) -> None:
        """``robot``: :class:`dbot.env.DbotEnv`'s keyword arguments, with its defaults (``model``,
        ``gait``, ``cycles_per_step``, ``max_episode_steps``, ``stiffness_nm_rad``, ``settle_s``,
        ``timeout_cycles``, ``reply_timeout_s``, ``fall_height_fraction``, ``fall_tilt_rad``,
        ``torques``), but ``reward`` and ``render_mode``: the reward is forward progress, and the
        robots are not drawn."""
        for fixed in ("reward", "render_mode"):
            if fixed in robot:
                raise TypeError(f"VectorEnv takes no {fixed!r}: see VectorEnv's docstring")
        # The spaces, limits and table are DbotEnv's own: one single environment built without
        # a robot (DbotEnv opens its robot only at reset).
        from .env import DbotEnv

        self._single = one = DbotEnv(f"physics:{scene}", **robot)
        if self._single.model.name != "drosophibot2":
            raise ValueError(
                f"model {self._single.model.name}: the physics robot is Drosophibot II"
            )
        self.num_envs = int(num_envs)
        if threads is None:
            threads = 0 if self.num_envs == 1 else min(self.num_envs, os.cpu_count() or 1)
        self.threads = int(threads)
        self.torques = one.torques
        self.single_observation_space = self._single.observation_space
        assert isinstance(self.single_observation_space, spaces.Dict)
        #: The observation's keys, in the order the core gives them.
        self._obs_keys: list[str] = list(self.single_observation_space.spaces)
        self.single_action_space = self._single.action_space
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.joint_names = self._single.joint_names
        self.strain_names = self._single.strain_names
        self.rest_rad = np.zeros((self.num_envs, len(self.joint_names)))
        self._low = self._single._angles_space.low
        self._high = self._single._angles_space.high
        self._stall = self._single.stall_nm
        if self.threads < 0:
            raise ValueError(f"threads = {self.threads}: give 0 (the calling thread) or more")
        options = VectorOptions(
            one._table,
            scene,
            one.cycles_per_step,
            one.max_episode_steps,
            one.stiffness_nm_rad,
            one.settle_s,
            one.timeout_cycles,
            one.reply_timeout_s,
            one.fall_height_fraction,
            one.fall_tilt_rad,
            cheap_reset,
        )
        # The core clips the actions to the action space's bounds (np.clip's rule) and builds
        # the step's observation and info dicts itself: the wrapper's per-step Python was about
        # a tenth of the single step (docs/performance.md, issue 38).
        self._core = VectorCore(
            self.num_envs,
            self.threads,
            options,
            low=[float(x) for x in self._low],
            high=[float(x) for x in self._high],
            stall=[float(x) for x in self._stall],
            obs_keys=self._obs_keys,
        )
        self._np_randoms: list[np.random.Generator] = [
            np.random.default_rng() for _ in range(self.num_envs)
        ]
        self.render_mode = None

    # -- Gymnasium API --------------------------------------------------------------------------

    def reset(
        self,
        *,
        seed: int | Sequence[int | None] | None = None,
        options: dict[str, Any] | None = None,
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        options = dict(options or {})
        mask = options.pop("reset_mask", None)
        mask = (
            np.ones(self.num_envs, dtype=bool)
            if mask is None
            else np.asarray(mask, dtype=bool).reshape(self.num_envs)
        )
        scene = options.pop("scene", None)
        stiffness = options.pop("stiffness_nm_rad", None)
        if options:
            raise ValueError(f"unknown reset options: {', '.join(sorted(options))}")
        seeds = self._seeds(seed)
        for i, s in enumerate(seeds):
            if mask[i] and s is not None:
                self._np_randoms[i], _ = seeding.np_random(s)
        if seed is not None:
            self.action_space.seed(None if isinstance(seed, Sequence) else seed)
        rows = self._core.reset(
            mask, None if scene is None else str(scene),
            None if stiffness is None else float(stiffness),
        )
        self._note_rest(rows, mask)
        return self._obs(rows), self._infos(rows, mask)

    def step(
        self, actions: Any
    ) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        angles, torques = self._split(actions)
        obs, reward, terminated, truncated, infos, rest = self._core.step_env(angles, torques)
        if rest is not None:  # an autoreset: the resting posture of the robots reset
            resetting, rest_rad = rest
            self.rest_rad[resetting] = rest_rad[resetting]
        return obs, reward, terminated, truncated, infos

    def close_extras(self, **kwargs: Any) -> None:
        core = getattr(self, "_core", None)  # absent when __init__ failed
        if core is not None:
            core.close()

    @property
    def np_randoms(self) -> list[np.random.Generator]:
        """Each sub-environment's random generator (seeded by ``reset(seed=...)``)."""
        return self._np_randoms

    # -- helpers --------------------------------------------------------------------------------

    def _seeds(self, seed: int | Sequence[int | None] | None) -> list[int | None]:
        if seed is None:
            return [None] * self.num_envs
        if isinstance(seed, (int, np.integer)):
            return [int(seed) + i for i in range(self.num_envs)]
        seeds = list(seed)
        if len(seeds) != self.num_envs:
            raise ValueError(f"seed: {len(seeds)} seeds for {self.num_envs} sub-environments")
        return seeds

    def _split(self, actions: Any) -> tuple[np.ndarray, np.ndarray | None]:
        """The joint targets (N x 22) and, with ``torques=True``, the torques (the core clips
        them to the action space's bounds)."""
        if not self.torques:
            return self._rows(actions, "actions"), None
        a = self._rows(actions["angles_rad"], 'actions["angles_rad"]')
        t = self._rows(actions["torques_nm"], 'actions["torques_nm"]')
        return a, t

    def _rows(self, v: Any, what: str) -> np.ndarray:
        a = np.asarray(v, dtype=np.float64)
        shape = (self.num_envs, len(self.joint_names))
        if a.shape != shape:
            raise ValueError(
                f"{what}: shape {a.shape}, give {shape}: one row of joint values per sub-environment"
            )
        return a

    def _note_rest(self, rows: dict[str, Any], mask: np.ndarray) -> None:
        # The resting posture each robot held at reset: its first setpoint's targets.
        self.rest_rad[mask] = rows["rest_rad"][mask]

    def _obs(self, rows: dict[str, Any]) -> dict[str, np.ndarray]:
        return {k: rows[k] for k in self._obs_keys}

    def _infos(self, rows: dict[str, Any], mask: np.ndarray) -> dict[str, Any]:
        body = {
            "thorax_position_m": rows["thorax_position_m"],
            "_thorax_position_m": mask.copy(),
            "thorax_orientation": rows["thorax_orientation"],
            "_thorax_orientation": mask.copy(),
        }
        return {
            "time_s": rows["time_s"],
            "_time_s": mask.copy(),
            "settle_skipped": rows["settle_skipped"],
            "_settle_skipped": mask.copy(),
            "state": np.array(rows["state"], dtype=object),
            "_state": mask.copy(),
            "body": body,
            "_body": mask.copy(),
        }


class SubEnv(gym.Env):
    """One robot of the Rust core as a plain ``gymnasium.Env`` (a :class:`VectorEnv` of one):
    what each sub-environment of a :class:`VectorEnv` is, for ``gymnasium.utils.env_checker``
    and for code that takes a single environment. Arguments as :class:`VectorEnv`'s."""

    metadata = {"render_modes": []}

    def __init__(self, **kwargs: Any) -> None:
        self._vec = VectorEnv(1, threads=1, **kwargs)
        self.observation_space = self._vec.single_observation_space
        self.action_space = self._vec.single_action_space

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        super().reset(seed=seed)
        obs, infos = self._vec.reset(seed=seed, options=options)
        return self._one(obs), self._info(infos)

    def step(self, action: Any) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        batched = (
            {k: np.asarray(v)[None] for k, v in action.items()}
            if isinstance(action, dict)
            else np.asarray(action)[None]
        )
        obs, reward, terminated, truncated, infos = self._vec.step(batched)
        return self._one(obs), float(reward[0]), bool(terminated[0]), bool(truncated[0]), self._info(infos)

    @property
    def rest_rad(self) -> np.ndarray:
        """The resting posture held at reset, rad."""
        return self._vec.rest_rad[0]

    @staticmethod
    def _one(obs: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        return {k: v[0] for k, v in obs.items()}

    @staticmethod
    def _info(infos: dict[str, Any]) -> dict[str, Any]:
        body = infos["body"]
        return {
            "time_s": float(infos["time_s"][0]),
            "state": str(infos["state"][0]),
            "body": {k: v[0] for k, v in body.items() if not k.startswith("_")},
        }

    def close(self) -> None:
        self._vec.close()

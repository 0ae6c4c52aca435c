"""Rollouts batched over workers that each hold an environment: :class:`RolloutPool`, over Ray
actors (a local cluster or any cluster by its address), a process pool, or this process.

Each worker builds its environment once (``make_env()``, e.g. a :class:`dbot.env.VectorEnv` of a
few robots on the calling thread) and keeps it, so later resets are the cheap ones (the stored
settled state) and no worker pays an import or a robot's construction per rollout. A call
``pool.map(fn, items)`` splits ``items`` into one contiguous chunk per worker and runs
``fn(env, chunk) -> rows`` (one row per item) on each: one Ray call or one pool task per worker
and call, however many items, which is what makes Ray pay on a small machine (its own docs: no
speed-up from tasks under about 10 ms; a rollout is hundreds of milliseconds, a chunk seconds).
The rows come back in the items' order; with Ray, :attr:`RolloutPool.nodes` names the node that
ran each item.

Everything the robots do is deterministic, so every backend gives the same rows as one process
(python/tests/test_ray_cluster.py checks it on a two-node cluster).

:func:`residual_walks` is the rollout the learning example trains with
(python/examples/learn_residual.py): residual joint targets around the planned gait.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from typing import Any

import numpy as np

#: The largest residual, rad (tanh bounds it): small beside the joints' ranges, so the policy
#: shapes the gait rather than replaces it.
SCALE_RAD = 0.15
#: The blend from the resting posture into the plan, s.
BLEND_S = 0.5
#: Bus cycle, s (`VectorEnv` steps one cycle per step).
CYCLE_S = 0.01
#: What a fall costs, m: more than any walk of an episode covers, so no lunge that ends in a
#: fall beats walking.
FALL_PENALTY_M = 1.0


@dataclass
class Gait:
    """The planned gait, tabulated per slice over one period: servo joint angles and torques."""

    angles: np.ndarray  # [slice, joint], rad
    torques: np.ndarray  # [slice, joint], N m, clipped to the stall torques
    period_s: float

    @classmethod
    def of(cls, model: Any = None, slices: int = 50) -> "Gait":
        """The default plan of ``model`` (None: the built-in Drosophibot II)."""
        import dbot

        model = model if model is not None else dbot.Model.builtin("drosophibot2")
        plan = dbot.plan(model, slices=slices)
        cols = np.asarray(model.servo_joints)
        stall = np.asarray(model.servo_stall_torques_nm)
        return cls(
            np.asarray(plan.angles)[:, cols],
            np.clip(np.asarray(plan.torques)[:, cols], -stall, stall),
            float(plan.period_s),
        )

    def at(self, k: int) -> tuple[float, np.ndarray, np.ndarray]:
        """Phase (fraction of the period), planned angles and torques at step ``k``."""
        phase = (k * CYCLE_S / self.period_s) % 1.0
        s = int(phase * len(self.angles)) % len(self.angles)
        return phase, self.angles[s], self.torques[s]


def residual(theta: np.ndarray, phase: float) -> np.ndarray:
    """The residual joint targets of parameters ``theta`` (3 x 22: A, B, b) at ``phase``, rad:
    ``SCALE_RAD * tanh(b + A sin(2 pi phase) + B cos(2 pi phase))`` per joint."""
    a, b, c = np.split(np.asarray(theta, dtype=np.float64), 3)
    w = 2.0 * math.pi * phase
    return SCALE_RAD * np.tanh(c + a * math.sin(w) + b * math.cos(w))


def residual_walks(env: Any, thetas: Sequence[np.ndarray], steps: int) -> list[float]:
    """Each of ``thetas`` walked for ``steps`` steps on its own robot of ``env`` (a
    :class:`dbot.env.VectorEnv` with ``torques=True``; at most ``env.num_envs`` at once): the
    planned angles plus the residual, the plan's torques as feed-forward, both blended in from
    the resting posture over ``BLEND_S``. Returns each one's fitness: the distance covered along
    x, m, less ``FALL_PENALTY_M`` if it fell."""
    params = np.asarray(thetas, dtype=np.float64).reshape(len(thetas), -1)
    gait = _gait()
    out = np.zeros(len(thetas))
    n = env.num_envs
    for first in range(0, len(thetas), n):
        batch = params[first : first + n]
        rows = np.zeros((n, params.shape[1]))
        rows[: len(batch)] = batch
        env.reset()
        rest = env.rest_rad.copy()
        total = np.zeros(n)
        alive = np.ones(n, dtype=bool)
        fell = np.zeros(n, dtype=bool)
        for k in range(steps):
            phase, angles, torques = gait.at(k)
            blend = min(1.0, k * CYCLE_S / BLEND_S)
            target = (1 - blend) * rest + blend * (
                angles[None, :] + np.stack([residual(t, phase) for t in rows])
            )
            action = {"angles_rad": target, "torques_nm": np.repeat(blend * torques[None], n, 0)}
            _, reward, terminated, truncated, _ = env.step(action)
            total += np.where(alive, reward, 0.0)
            fell |= alive & terminated
            alive &= ~(terminated | truncated)
        fitness = total - FALL_PENALTY_M * fell
        out[first : first + len(batch)] = fitness[: len(batch)]
    return [float(x) for x in out]


_GAIT: Gait | None = None


def _gait() -> Gait:
    """The default plan's gait, planned once per process."""
    global _GAIT
    if _GAIT is None:
        _GAIT = Gait.of()
    return _GAIT


# -- the pool ------------------------------------------------------------------------------------

#: The environment a process-pool worker holds (built by the pool's initializer).
_ENV: Any = None


def _init_worker(make_env: Callable[[], Any]) -> None:
    global _ENV
    _ENV = make_env()


def _run_in_worker(fn: Callable[[Any, list], list], chunk: list) -> list:
    return fn(_ENV, chunk)


def _chunks(items: Sequence[Any], k: int) -> list[list[Any]]:
    """``items`` in at most ``k`` contiguous chunks of sizes differing by at most one."""
    k = max(1, min(k, len(items)))
    q, r = divmod(len(items), k)
    out, start = [], 0
    for i in range(k):
        end = start + q + (1 if i < r else 0)
        out.append(list(items[start:end]))
        start = end
    return out


class RolloutPool:
    """Workers that each hold an environment from ``make_env`` and run rollouts in chunks.

    ``backend``: ``"ray"`` (one actor per worker, each reserving one CPU: ``ray.init(address)``
    is called unless Ray is initialised already; None starts a local cluster), ``"processes"``
    (a process pool of ``workers``), ``"serial"`` (this process, one environment).
    ``workers``: how many (default: Ray's CPUs, or the machine's)."""

    def __init__(
        self,
        make_env: Callable[[], Any],
        backend: str = "ray",
        *,
        workers: int | None = None,
        address: str | None = None,
    ) -> None:
        import os

        self.backend = backend
        #: The node that ran each item of the last ``map`` (Ray only; else None).
        self.nodes: list[str] | None = None
        if backend == "serial":
            self.workers = 1
            self._env = make_env()
        elif backend == "processes":
            self.workers = workers or os.cpu_count() or 1
            self._pool = ProcessPoolExecutor(
                max_workers=self.workers, initializer=_init_worker, initargs=(make_env,)
            )
        elif backend == "ray":
            import ray

            if not ray.is_initialized():
                ray.init(address=address, include_dashboard=False, log_to_driver=False)
            self.workers = workers or int(ray.cluster_resources().get("CPU", 1))
            holder = ray.remote(num_cpus=1)(_EnvHolder)
            #: Ray actor handles (Ray's types do not follow `ray.remote` on a class).
            self._actors: list[Any] = [holder.remote(make_env) for _ in range(self.workers)]
        else:
            raise ValueError(f"backend {backend!r}: give ray, processes or serial")

    def map(self, fn: Callable[[Any, list], list], items: Sequence[Any]) -> list:
        """``fn(env, chunk)`` over ``items`` in one chunk per worker; rows in the items' order."""
        chunks = _chunks(items, self.workers)
        if self.backend == "serial":
            return [row for c in chunks for row in fn(self._env, c)]
        if self.backend == "processes":
            return [row for rows in self._pool.map(_run_in_worker, [fn] * len(chunks), chunks)
                    for row in rows]
        import ray

        done = ray.get([a.run.remote(fn, c) for a, c in zip(self._actors, chunks)])
        self.nodes = [node for node, rows in done for _ in rows]
        return [row for _, rows in done for row in rows]

    def close(self) -> None:
        if self.backend == "processes":
            self._pool.shutdown()
        elif self.backend == "ray":
            import ray

            for a in self._actors:
                ray.kill(a)
        elif self._env is not None:
            self._env.close()

    def __enter__(self) -> "RolloutPool":
        return self

    def __exit__(self, *_: object) -> None:
        self.close()


class _EnvHolder:
    """A Ray actor holding one environment (made a remote class by :class:`RolloutPool`)."""

    def __init__(self, make_env: Callable[[], Any]) -> None:
        self.env = make_env()

    def run(self, fn: Callable[[Any, list], list], chunk: list) -> tuple[str, list]:
        import ray

        return ray.get_runtime_context().get_node_id(), fn(self.env, chunk)

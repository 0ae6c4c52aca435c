"""Sweeps over environment rollouts: one rollout per parameter set, one tidy row of figures each,
run in one process, over a process pool, or on a Ray cluster (a local one, or any cluster by its
address: the same code).

A rollout is a top-level function ``params -> row`` (so it can be sent to another process or
machine). :func:`gait_rollout` is the one provided: it plans a gait with the stepping parameters
in ``params`` (``dbot.plan``'s keyword arguments: ``swing_s``, ``translation_m``,
``step_height_m``, ...), plays it open loop through :class:`dbot.env.DbotEnv` on the physics
robot (the plan's joint angles at the time's phase, its torques as the setpoint's torque
feed-forward) and measures:

* ``distance_m``: the thorax's advance along world x;
* ``slip_m``: the distance the loaded feet slid (foot slip speed x dt, summed over feet);
* ``energy_j``: the mechanical work of the servos, sum over servos and bus cycles of
  |torque x angular velocity| x dt (:func:`mechanical_energy_j`), from the observation alone (so
  the same figure on a board): the angular velocity is the servos' Present Velocity
  (``velocity_rad_s``), the torque an ESTIMATE from their load registers (``load_raw`` through
  ``Model.load_torques_nm``: MX-28 load x stall torque, MX-64 current x stall torque / stall
  current), not the simulation's actuator torque. Absolute values: braking work counts too (a
  servo spends energy holding back as well as pushing);
* ``tracking_rad``: RMS of target - present angle over every servo and bus cycle, the target
  being the plan's angle sent (the action's ``angles_rad``; the firmware adds the torque bias
  on top, which is meant to bring the present angle onto it);
* ``fell``: whether the episode ended in a fall or a firmware fault (``DbotEnv``'s rule);
* ``sim_s``: simulated time.

Rollouts are deterministic (fixed seed, simulated time), so every backend gives the same rows.

    rows = sweep(gait_rollout, grid(translation_m=[0.04, 0.085], swing_s=[0.8, 1.0]))
    rows = sweep(gait_rollout, points, backend="ray")                      # local cluster
    rows = sweep(gait_rollout, points, backend="ray", address="ray://head:10001")
    print(table(rows)); plot_pareto(rows, "distance_m", "energy_j", "pareto.png")
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor
from typing import Any

import numpy as np

Row = dict[str, Any]
Rollout = Callable[[dict[str, Any]], Row]


def grid(**axes: Sequence[Any]) -> list[dict[str, Any]]:
    """Every combination of the axes' values, e.g. ``grid(a=[1, 2], b=[3])``."""
    keys = list(axes)
    return [dict(zip(keys, values, strict=True)) for values in itertools.product(*axes.values())]


def mechanical_energy_j(torque_nm: np.ndarray, velocity_rad_s: np.ndarray, dt_s: float) -> float:
    """Mechanical work, J: sum over samples and joints of |torque x angular velocity| x ``dt_s``
    (``torque_nm`` and ``velocity_rad_s`` [sample, joint], N m and rad/s, one sample per
    ``dt_s``)."""
    tau = np.asarray(torque_nm, dtype=np.float64)
    omega = np.asarray(velocity_rad_s, dtype=np.float64)
    if tau.shape != omega.shape:
        raise ValueError(f"torque_nm has shape {tau.shape}, velocity_rad_s {omega.shape}: give the same")
    return float(np.sum(np.abs(tau * omega)) * dt_s)


def gait_rollout(params: dict[str, Any]) -> Row:
    """Plans ``params``' gait and plays ``cycles`` (default 2) step periods of it open loop on
    ``port`` (default ``physics``); returns ``params`` with the figures (module docstring)."""
    import dbot
    from dbot.env import DbotEnv

    p = dict(params)
    cycles = float(p.pop("cycles", 2.0))
    port = str(p.pop("port", "physics"))
    seed = int(p.pop("seed", 0))
    model = dbot.Model.builtin("drosophibot2")
    plan = dbot.plan(model, slices=int(p.pop("slices", 50)), **p)
    cols = np.array(model.servo_joints)
    angles, torques = plan.angles[:, cols], plan.torques[:, cols]
    stall = np.asarray(model.servo_stall_torques_nm)
    dt = 0.01
    steps = int(round(cycles * plan.period_s / dt))
    env = DbotEnv(port, model=model, gait=plan, torques=True, max_episode_steps=steps + 1)
    obs, info = env.reset(seed=seed)
    rest = env.rest_rad
    x0 = info["body"]["thorax_position_m"][0]
    slip, err2, n_err, fell = 0.0, 0.0, 0, False
    torque, velocity = [], []
    blend_s = 0.5
    for k in range(steps):
        t = k * dt
        s = (t / plan.period_s * plan.slices) % plan.slices
        s0 = int(s)
        s1, w = (s0 + 1) % plan.slices, s - s0
        q = (1 - w) * angles[s0] + w * angles[s1]
        tau = np.clip((1 - w) * torques[s0] + w * torques[s1], -stall, stall)
        b = min(1.0, t / blend_s)
        target = (1 - b) * rest + b * q
        obs, _, terminated, _, info = env.step({"angles_rad": target, "torques_nm": b * tau})
        body = info["body"]
        slip += float(np.sum(np.asarray(body["foot_slip_m_s"]) * np.asarray(body["foot_contact"]))) * dt
        err2 += float(np.sum((obs["present_rad"] - target) ** 2))
        n_err += target.size
        torque.append(model.load_torques_nm(obs["load_raw"]))
        velocity.append(obs["velocity_rad_s"])
        if terminated:
            fell = True
            break
    env.close()
    row = dict(params)
    row.update(
        distance_m=float(info["body"]["thorax_position_m"][0] - x0),
        slip_m=slip,
        energy_j=mechanical_energy_j(np.array(torque), np.array(velocity), dt) if torque else 0.0,
        tracking_rad=math.sqrt(err2 / max(n_err, 1)),
        fell=fell,
        sim_s=float(info["time_s"]),
    )
    return row


def _each(rollout: Rollout, points: Sequence[dict[str, Any]]) -> list[Row]:
    return [rollout(p) for p in points]


def sweep(
    rollout: Rollout,
    points: Sequence[dict[str, Any]],
    backend: str = "serial",
    *,
    processes: int | None = None,
    address: str | None = None,
    num_cpus: int | None = None,
) -> list[Row]:
    """One row per point, in the points' order. ``backend``: ``serial`` (this process),
    ``processes`` (a pool of ``processes`` worker processes) or ``ray`` (``ray.init(address)``:
    ``None`` starts a local cluster with ``num_cpus`` CPUs, an address joins that cluster; a Ray
    already initialised in this process is used as it is; one task per CPU of the cluster, each
    a contiguous chunk of the points)."""
    if backend == "serial":
        return [rollout(p) for p in points]
    if backend == "processes":
        with ProcessPoolExecutor(max_workers=processes) as pool:
            return list(pool.map(rollout, points))
    if backend == "ray":
        import ray

        if not ray.is_initialized():
            ray.init(address=address, num_cpus=num_cpus, include_dashboard=False,
                     log_to_driver=False)
        # One task per CPU of the cluster, each a contiguous chunk of the points (Ray's own
        # advice: batch tasks; docs/performance.md, "Many robots at once").
        from .vector_pool import _chunks

        cpus = max(1, int(ray.cluster_resources().get("CPU", 1)))
        remote = ray.remote(_each)
        done = ray.get([remote.remote(rollout, c) for c in _chunks(points, cpus)])
        return [row for rows in done for row in rows]
    raise ValueError(f"backend {backend!r}: give serial, processes or ray")


def table(rows: Sequence[Row], floats: str = ".4g") -> str:
    """The rows as a Markdown table (one column per key, in first-seen order)."""
    keys: list[str] = []
    for r in rows:
        keys += [k for k in r if k not in keys]

    def cell(v: Any) -> str:
        if isinstance(v, float):
            return format(v, floats)
        return str(v)

    lines = ["| " + " | ".join(keys) + " |", "|" + "---|" * len(keys)]
    lines += ["| " + " | ".join(cell(r.get(k, "")) for k in keys) + " |" for r in rows]
    return "\n".join(lines)


def pareto(rows: Sequence[Row], maximise: str, minimise: str) -> list[int]:
    """Indices of the rows on the Pareto front of high ``maximise`` and low ``minimise`` (rows
    that fell are left out): no other row is at least as good in both and better in one."""
    ok = [i for i, r in enumerate(rows) if not r.get("fell", False)]
    front = []
    for i in ok:
        a, b = rows[i][maximise], rows[i][minimise]
        dominated = any(
            rows[j][maximise] >= a and rows[j][minimise] <= b
            and (rows[j][maximise] > a or rows[j][minimise] < b)
            for j in ok
        )
        if not dominated:
            front.append(i)
    return sorted(front, key=lambda i: rows[i][maximise])


def plot_pareto(rows: Sequence[Row], maximise: str, minimise: str, path: str) -> list[int]:
    """Scatter of every row (falls as crosses) with the Pareto front drawn; returns the front."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    front = pareto(rows, maximise, minimise)
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for r in rows:
        ax.plot(r[maximise], r[minimise], "rx" if r.get("fell") else "ko", markersize=5)
    ax.plot([rows[i][maximise] for i in front], [rows[i][minimise] for i in front], "C0-o",
            label="Pareto front")
    ax.set_xlabel(f"{maximise} (higher is better)")
    ax.set_ylabel(f"{minimise} (lower is better)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return front

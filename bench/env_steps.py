"""Research-environment throughput (issue 27): `DbotEnv` steps per second on one core with the
firmware in the loop, the firmware's (and Python's) share against a bare MuJoCo rollout of the
same model, and rollouts per second in one process, over N processes and on a local Ray cluster.

    .venv/bin/python bench/env_steps.py                 # the figures of docs/performance.md
    .venv/bin/python bench/env_steps.py --quick         # a short run that checks it still works

One core: the process is pinned to CPU 0 (`os.sched_setaffinity`) for the single-process figures;
CPU time is the process's (`time.process_time`), wall time is printed beside it. The bare rollout
is the official `mujoco` package (3.17.0, the same library as the physics robot) stepping the MJCF
export of Drosophibot II (`dbot model export --mjcf`) at the physics robot's 1 ms timestep with
islands off, ten steps per bus cycle, its actuators holding the stance keyframe: the same body and
contacts without the firmware, the simulated bus, the link and Python.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]


def env_steps(steps: int, walk: bool) -> dict[str, float]:
    """Times `steps` calls of `DbotEnv.step` (nothing else): holding the resting posture with a
    small sine on every joint, or (`walk`) walking the default plan open loop with its torques as
    feed-forward, as `dbot.sweep.gait_rollout` does."""
    import dbot
    from dbot.env import DbotEnv

    model = dbot.Model.builtin("drosophibot2")
    plan = dbot.plan(model, slices=50)
    env = DbotEnv("physics", model=model, gait=plan, max_episode_steps=steps + 1, torques=True)
    env.reset(seed=0)
    rest = env.rest_rad
    cols = np.array(model.servo_joints)
    k = np.arange(steps)
    if walk:
        s = (k * 0.01 / plan.period_s * plan.slices).astype(int) % plan.slices
        blend = np.minimum(1.0, k * 0.01 / 0.5)[:, None]
        angles = (1 - blend) * rest + blend * plan.angles[s][:, cols]
        stall = np.asarray(model.servo_stall_torques_nm)
        torques = blend * np.clip(plan.torques[s][:, cols], -stall, stall)
    else:
        angles = rest + 0.02 * np.sin(k[:, None] * 0.05 + np.arange(rest.size)[None, :])
        torques = np.zeros_like(angles)
    actions = [{"angles_rad": a, "torques_nm": t} for a, t in zip(angles, torques, strict=True)]
    c0, w0 = time.process_time(), time.perf_counter()
    for a in actions:
        _, _, terminated, _, info = env.step(a)
        assert not terminated, "the robot fell: the benchmark's walk is broken"
    c1, w1 = time.process_time(), time.perf_counter()
    x = float(info["body"]["thorax_position_m"][0])
    env.close()
    return {"steps": steps, "cpu_s": c1 - c0, "wall_s": w1 - w0, "x_m": x}


def bare_model():  # noqa: ANN201 (mujoco's types)
    """The bare rollout's model and data: the MJCF export at the physics robot's 1 ms timestep,
    islands off, in the stance keyframe (its actuators holding it)."""
    import mujoco

    dbot_bin = ROOT / "target" / "debug" / "dbot"
    with tempfile.TemporaryDirectory() as d:
        xml = pathlib.Path(d) / "robot.xml"
        cmd = [str(dbot_bin)] if dbot_bin.exists() else ["cargo", "run", "--quiet", "-p", "dbot", "--"]
        subprocess.run(cmd + ["model", "export", "--model", "drosophibot2", "--mjcf", str(xml)],
                       cwd=ROOT, check=True, stdout=subprocess.DEVNULL)
        m = mujoco.MjModel.from_xml_path(str(xml))
    m.opt.timestep = 0.001
    m.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_ISLAND
    data = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, data, 0)
    return m, data


def bare_mujoco(cycles: int) -> dict[str, float]:
    import mujoco

    m, data = bare_model()
    c0, w0 = time.process_time(), time.perf_counter()
    for _ in range(cycles * 10):
        mujoco.mj_step(m, data)
    c1, w1 = time.process_time(), time.perf_counter()
    return {"cycles": cycles, "cpu_s": c1 - c0, "wall_s": w1 - w0}


def rollouts(n: int, processes: int, use_ray: bool) -> dict[str, float]:
    from dbot.sweep import gait_rollout, grid, sweep

    points = grid(translation_m=list(np.linspace(0.04, 0.09, n)), cycles=[1.0])
    out: dict[str, float] = {"rollouts": n}
    t = time.perf_counter()
    serial = sweep(gait_rollout, points)
    out["serial_s"] = time.perf_counter() - t
    t = time.perf_counter()
    pooled = sweep(gait_rollout, points, backend="processes", processes=processes)
    out["processes_s"] = time.perf_counter() - t
    assert pooled == serial, "a process pool gave other rows"
    if use_ray:
        import ray

        t = time.perf_counter()
        ray.init(num_cpus=processes, include_dashboard=False, log_to_driver=False)
        out["ray_init_s"] = time.perf_counter() - t
        t = time.perf_counter()
        rayed = sweep(gait_rollout, points, backend="ray")
        out["ray_s"] = time.perf_counter() - t
        ray.shutdown()
        assert rayed == serial, "Ray gave other rows"
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=5000, help="environment steps (bus cycles) timed")
    ap.add_argument("--rollouts", type=int, default=8)
    ap.add_argument("--processes", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--quick", action="store_true", help="200 steps, 2 rollouts, no Ray")
    args = ap.parse_args()
    steps, n, use_ray = (200, 2, False) if args.quick else (args.steps, args.rollouts, True)
    print(f"load average {os.getloadavg()[0]:.1f} {os.getloadavg()[1]:.1f} on {os.cpu_count()} cores")
    affinity = os.sched_getaffinity(0)
    os.sched_setaffinity(0, {min(affinity)})
    stand = env_steps(steps, walk=False)
    e = env_steps(steps, walk=True)
    b = bare_mujoco(steps)
    os.sched_setaffinity(0, affinity)
    env_rate = e["steps"] / e["cpu_s"]
    bare_rate = b["cycles"] / b["cpu_s"]
    print(f"DbotEnv physics, firmware in the loop, standing: {stand['steps'] / stand['cpu_s']:.0f} steps/s CPU "
          f"({stand['steps'] / stand['wall_s']:.0f} wall)")
    print(f"DbotEnv physics, firmware in the loop, walking ({e['x_m']:.2f} m): {env_rate:.0f} steps/s CPU "
          f"({e['steps'] / e['wall_s']:.0f} wall), {env_rate / 100:.1f}x real time at 10 ms per step")
    print(f"bare MuJoCo, same model, 10 x 1 ms per cycle: {bare_rate:.0f} cycles/s CPU "
          f"({b['cycles'] / b['wall_s']:.0f} wall)")
    print(f"firmware, bus, link and Python: {100 * (1 - env_rate / bare_rate):.0f} % of a walking "
          "environment step (the bare rollout stands: contacts of a walk cost MuJoCo more)")
    r = rollouts(n, args.processes, use_ray)
    print(f"rollouts of 1 planned cycle ({n}): one process {n / r['serial_s']:.2f}/s, "
          f"{args.processes} processes {n / r['processes_s']:.2f}/s"
          + (f", Ray local cluster {n / r['ray_s']:.2f}/s (its start {r['ray_init_s']:.1f} s)" if use_ray else ""))
    if args.quick:
        print("bench/env_steps.py --quick: ran")


if __name__ == "__main__":
    sys.exit(main())

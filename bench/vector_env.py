"""Many robots at once (issue 38), measured side by side in one run: `dbot.env.VectorEnv`
throughput for N = 1 and 2, the single environment's overhead against bare MuJoCo stepping the
same model, a reset against stepping the same simulated span, and rollouts over Ray actors
against a process pool (`dbot.vector_pool.RolloutPool`).

The overhead columns are issue 38's: (environment - bare MuJoCo) / bare MuJoCo, CPU time per step
of one environment against bare MuJoCo stepping the same model for the same 10 ms, what the
firmware, bus, link and Python add as a share of the physics (target: at most 15 %). Standing:
each environment built once and stepped past its reset's transient, in short blocks each paired
with a block of bare MuJoCo (the median of the pairs, and their middle half: the machine's speed
drifts within a run). After a reset: a fresh robot per round of a third of the steps, its
physics still settling for the first seconds (MuJoCo's own work is then a few percent higher, which
this column counts as overhead too).

    .venv/bin/python bench/vector_env.py            # the figures of docs/performance.md
    .venv/bin/python bench/vector_env.py --quick    # a short run that checks it still works
    .venv/bin/python bench/vector_env.py --standing # the standing overhead alone (two builds: A/B)

Needs the package built optimised (scripts/setup.d/40-python.sh: `maturin develop --profile
quick-release`); `target/debug/dbot` or cargo for the MJCF export of the bare MuJoCo rollout.
BLAS is pinned to one thread (it otherwise spins threads of its own on every NumPy call).
CPU times are the process's (`time.process_time`: every thread of it, the worker threads
included); wall times are printed beside them. The machine's load average is printed first and
last: on a shared machine, wall times depend on it.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse  # noqa: E402
import functools  # noqa: E402
import pathlib  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402

import numpy as np  # noqa: E402

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from env_steps import bare_model, bare_mujoco  # noqa: E402

from dbot.env import DbotEnv, VectorEnv  # noqa: E402
from dbot.vector_pool import RolloutPool, residual_walks  # noqa: E402


def wiggle(rest: np.ndarray, k: int) -> np.ndarray:
    """Joint targets near the resting posture (the robot stands, no episode ends)."""
    return rest + 0.02 * np.sin(k * 0.05 + np.arange(rest.shape[-1]))


def vector_rate(n: int, threads: int, steps: int) -> dict[str, float]:
    env = VectorEnv(n, threads=threads, max_episode_steps=steps + 10)
    env.reset(seed=0)
    rest = env.rest_rad.copy()
    acts = [wiggle(rest, k) for k in range(steps)]
    c0, w0 = time.process_time(), time.perf_counter()
    for a in acts:
        env.step(a)
    c1, w1 = time.process_time(), time.perf_counter()
    env.close()
    return {"robot_steps": n * steps, "cpu_s": c1 - c0, "wall_s": w1 - w0}


def core_rate(steps: int) -> dict[str, float]:
    """`VectorEnv(1, threads=0)`'s Rust core alone (`VectorCore.step_env`, which clips the
    actions and builds the observation and info dicts): the step without the Gymnasium
    wrapper's Python (the action's shape check, the resting posture after an autoreset)."""
    env = VectorEnv(1, threads=0, max_episode_steps=steps + 10)
    env.reset(seed=0)
    rest = env.rest_rad.copy()
    acts = [wiggle(rest, k) for k in range(steps)]
    core = env._core
    c0, w0 = time.process_time(), time.perf_counter()
    for a in acts:
        core.step_env(a, None)
    c1, w1 = time.process_time(), time.perf_counter()
    env.close()
    return {"robot_steps": steps, "cpu_s": c1 - c0, "wall_s": w1 - w0}


def dbot_env_rate(steps: int) -> dict[str, float]:
    env = DbotEnv("physics", max_episode_steps=steps + 10)
    env.reset(seed=0)
    acts = [wiggle(env.rest_rad, k) for k in range(steps)]
    c0, w0 = time.process_time(), time.perf_counter()
    for a in acts:
        env.step(a)
    c1, w1 = time.process_time(), time.perf_counter()
    env.close()
    return {"robot_steps": steps, "cpu_s": c1 - c0, "wall_s": w1 - w0}


def steady_blocks(blocks: int, per: int, warm: int) -> dict[str, list[float]]:
    """CPU time (s) of ``blocks`` short blocks of ``per`` steps of each single environment, each
    block beside bare MuJoCo's block of the same span: every environment built once and stepped
    ``warm`` steps past its reset first, bare MuJoCo likewise, then the blocks interleaved (for
    each environment in turn a block of bare MuJoCo, then the environment's). Blocks of a few tens of milliseconds pair each environment with bare
    MuJoCo at the same machine speed; stepping past the reset compares the standing robot with
    the standing bare model (in the first few seconds after a reset MuJoCo itself works about 6 %
    harder on the physics robot's settling body, counted in instructions: docs/performance.md)."""
    import mujoco

    m, data = bare_model()
    n = warm + blocks * per + 10
    made = {
        "core": VectorEnv(1, threads=0, max_episode_steps=n),
        "inline": VectorEnv(1, threads=0, max_episode_steps=n),
        "worker1": VectorEnv(1, threads=1, max_episode_steps=n),
        "single": DbotEnv("physics", max_episode_steps=n),
    }
    steppers: dict[str, Callable[[np.ndarray], object]] = {}
    acts: dict[str, list[np.ndarray]] = {}
    for k, env in made.items():
        env.reset(seed=0)
        rest = env.rest_rad.copy()
        acts[k] = [wiggle(rest, i) for i in range(warm + blocks * per)]
        steppers[k] = (lambda a, c=env._core: c.step_env(a, None)) if k == "core" else env.step
    for _ in range(warm * 10):
        mujoco.mj_step(m, data)
    for k, step in steppers.items():
        for a in acts[k][:warm]:
            step(a)
    got: dict[str, list[float]] = {k: [] for k in steppers}
    bare: dict[str, list[float]] = {k: [] for k in steppers}
    for b in range(blocks):
        for k, step in steppers.items():
            c = time.process_time()
            for _ in range(per * 10):
                mujoco.mj_step(m, data)
            bare[k].append(time.process_time() - c)
            todo = acts[k][warm + b * per:warm + (b + 1) * per]
            c = time.process_time()
            for a in todo:
                step(a)
            got[k].append(time.process_time() - c)
    for env in made.values():
        env.close()
    return {"bare": [t for k in steppers for t in bare[k]], **got,
            **{f"bare_{k}": v for k, v in bare.items()}}


def standing_only() -> int:
    """The standing overhead of every single environment, one core, 40 blocks of 100 steps."""
    affinity = os.sched_getaffinity(0)
    os.sched_setaffinity(0, {min(affinity)})
    steady = steady_blocks(40, 100, 300)
    os.sched_setaffinity(0, affinity)
    import dbot

    print(f"package: {pathlib.Path(dbot.__file__).parent}")
    print("| standing, one core, 40 blocks of 100 steps | us per step | overhead (middle half) |")
    print("|---|---|---|")
    print(f"| bare MuJoCo | {1e4 * np.median(steady['bare']):.0f} | - |")
    for k in ("core", "inline", "worker1", "single"):
        pairs = [e / b - 1 for e, b in zip(steady[k], steady[f"bare_{k}"])]
        q1, q3 = np.percentile(pairs, [25, 75])
        print(f"| {k} | {1e4 * np.median(steady[k]):.0f} | {100 * np.median(pairs):.1f} % "
              f"({100 * q1:.1f} to {100 * q3:.1f}) |")
    return 0


def resets(repeats: int) -> dict[str, float]:
    """Median CPU time of a full reset, a cheap one, and of stepping the settling's span."""
    out: dict[str, list[float]] = {"full": [], "cheap": [], "span": []}
    for cheap in (False, True):
        env = VectorEnv(1, threads=0, cheap_reset=cheap, max_episode_steps=1000)
        env.reset()  # the first reset simulates the settling either way
        for _ in range(repeats):
            c = time.process_time()
            _, info = env.reset()
            out["cheap" if cheap else "full"].append(time.process_time() - c)
            assert bool(info["settle_skipped"][0]) == cheap
        if cheap:
            # The span a reset settles for: the gravity ramp's 1 s and settle_s 0.5 s, 150 cycles.
            rest = env.rest_rad.copy()
            for _ in range(repeats):
                c = time.process_time()
                for k in range(150):
                    env.step(wiggle(rest, k))
                out["span"].append(time.process_time() - c)
        env.close()
    return {k: float(np.median(v)) for k, v in out.items()}


def pools(items: int, steps: int, workers: int, rounds: int) -> dict[str, float]:
    """Wall time of the same rollouts in one process, over a process pool and over Ray actors:
    every pool built and warmed by one call first (its start is reported apart), then ``rounds``
    rounds of one call each, interleaved; the median round."""
    import ray

    make_env = functools.partial(VectorEnv, 1, threads=0, max_episode_steps=steps, torques=True)
    walk = functools.partial(residual_walks, steps=steps)
    rng = np.random.default_rng(0)
    thetas = [rng.normal(0.0, 0.3, 66) for _ in range(items)]
    out: dict[str, float] = {"items": items, "steps": steps, "workers": workers}
    built = {}
    for backend in ("serial", "processes", "ray"):
        t = time.perf_counter()
        if backend == "ray":
            ray.init(num_cpus=workers, include_dashboard=False, log_to_driver=False)
        built[backend] = RolloutPool(make_env, backend, workers=workers)
        built[backend].map(walk, thetas[:workers])  # warm: every worker built its robot
        out[f"{backend}_start_s"] = time.perf_counter() - t
    times: dict[str, list[float]] = {b: [] for b in built}
    rows = {}
    for _ in range(rounds):
        for backend, pool in built.items():
            t = time.perf_counter()
            rows[backend] = pool.map(walk, thetas)
            times[backend].append(time.perf_counter() - t)
    for backend, pool in built.items():
        pool.close()
        out[f"{backend}_s"] = float(np.median(times[backend]))
    ray.shutdown()
    assert rows["processes"] == rows["serial"] == rows["ray"], "a backend gave other rows"
    return out


def rounds_of(
    rounds: int, runs: dict[str, Callable[[], dict[str, float]]]
) -> dict[str, list[dict[str, float]]]:
    """Each of ``runs`` ``rounds`` times, interleaved: per run its rounds in order."""
    got: dict[str, list[dict[str, float]]] = {k: [] for k in runs}
    for _ in range(rounds):
        for k, f in runs.items():
            got[k].append(f())
    return got


def median_of(
    rounds: int, runs: dict[str, Callable[[], dict[str, float]]], key: str = "cpu_s"
) -> dict[str, dict[str, float]]:
    """Each of ``runs`` ``rounds`` times, interleaved; per run the round of median ``key``."""
    got = rounds_of(rounds, runs)
    return {k: sorted(v, key=lambda m: m[key])[len(v) // 2] for k, v in got.items()}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=3000, help="steps per throughput figure")
    ap.add_argument("--quick", action="store_true", help="short: 200 steps, 2 x 2 rollouts")
    ap.add_argument("--standing", action="store_true",
                    help="only the standing overhead (about 15 s): for comparing two builds, "
                         "each run with its package first on PYTHONPATH, alternately")
    a = ap.parse_args()
    if a.standing:
        return standing_only()
    steps = 200 if a.quick else a.steps
    cpus = os.cpu_count() or 1
    print(f"load average at start: {' '.join(f'{x:.1f}' for x in os.getloadavg())} on {cpus} cores")

    rounds = 1 if a.quick else 3
    # One core: the single-environment figures, interleaved rounds of a third of the steps each,
    # three times as many; each environment's overhead is the median over the rounds of its
    # round against bare MuJoCo's in the same round (paired: the machine's speed drifts over a
    # run by more than the differences measured here).
    affinity = os.sched_getaffinity(0)
    os.sched_setaffinity(0, {min(affinity)})
    short = max(1, steps // 3)
    one = rounds_of(3 * rounds, {
        "bare": lambda: {**bare_mujoco(short), "robot_steps": short},
        "core": lambda: core_rate(short),
        "inline": lambda: vector_rate(1, 0, short),
        "worker1": lambda: vector_rate(1, 1, short),
        "single": lambda: dbot_env_rate(short),
    })
    us = {k: [1e6 * m["cpu_s"] / m["robot_steps"] for m in v] for k, v in one.items()}
    blocks, per_block = (3, 20) if a.quick else (40, 100)
    steady = steady_blocks(blocks, per_block, 30 if a.quick else 300)
    r = resets(3 if a.quick else 10)
    os.sched_setaffinity(0, affinity)

    # Every core: N = 1 and N = 2 side by side, interleaved rounds, medians (of wall time).
    both = median_of(rounds, {"n1": lambda: vector_rate(1, 1, steps),
                              "n2": lambda: vector_rate(2, 2, steps)}, key="wall_s")
    n1, n2 = both["n1"], both["n2"]

    per = lambda m: 1e6 * m["cpu_s"] / m["robot_steps"]  # noqa: E731
    # The overhead as issue 38 defines it: what the firmware, bus, link and Python add, as a
    # share of bare MuJoCo stepping the same model, (env - bare) / bare (target: at most 15 %).
    print(f"\n| what (one core, CPU time per step of 10 ms) | us per step, standing (median of "
          f"{blocks} blocks of {per_block} steps) | overhead: (this - bare) / bare, standing: "
          f"median of the blocks' pairs (middle half) | us per step, after a reset ({3 * rounds} "
          f"rounds of {short} steps, each a fresh robot) | overhead after a reset |")
    print("|---|---|---|---|---|")
    print(f"| bare MuJoCo, same model, 10 x 1 ms | {1e6 * np.median(steady['bare']) / per_block:.0f} "
          f"| - | {np.median(us['bare']):.0f} | - |")
    for name, k in (("its Rust core alone (VectorCore.step_env)", "core"),
                    ("VectorEnv(1, threads=0)", "inline"), ("VectorEnv(1, threads=1)", "worker1"),
                    ("DbotEnv", "single")):
        pairs = [e / b - 1 for e, b in zip(steady[k], steady[f"bare_{k}"])]
        q1, q3 = np.percentile(pairs, [25, 75])
        fresh = np.median([e / b - 1 for e, b in zip(us[k], us["bare"])])
        print(f"| {name} | {1e6 * np.median(steady[k]) / per_block:.0f} | "
              f"{100 * np.median(pairs):.1f} % ({100 * q1:.1f} to {100 * q3:.1f}) | "
              f"{np.median(us[k]):.0f} | {100 * fresh:.0f} % |")

    print("\n| vector throughput (every core) | robot steps/s, wall | x N = 1 | CPU us per robot step |")
    print("|---|---|---|---|")
    rate1 = n1["robot_steps"] / n1["wall_s"]
    rate2 = n2["robot_steps"] / n2["wall_s"]
    print(f"| N = 1 (1 worker thread) | {rate1:.0f} | 1.00 | {per(n1):.0f} |")
    print(f"| N = 2 (2 worker threads) | {rate2:.0f} | {rate2 / rate1:.2f} | {per(n2):.0f} |")

    print("\n| reset (one core, CPU time, median) | s | against stepping the span |")
    print("|---|---|---|")
    print(f"| stepping 1.5 s (150 steps: the settling's span) | {r['span']:.4f} | 1.00 |")
    print(f"| full reset (simulates the settling) | {r['full']:.4f} | {r['full'] / r['span']:.2f} |")
    print(f"| cheap reset (the stored settled state) | {r['cheap']:.4f} | {r['cheap'] / r['span']:.2f} |")

    p = pools(4 if a.quick else 8, 50 if a.quick else 250, cpus, rounds)
    print(f"\n| {p['items']} rollouts of {p['steps']} steps, {p['workers']} workers (wall) "
          "| s | rollouts/s | x process pool | start (built, warmed) |")
    print("|---|---|---|---|---|")
    for b in ("serial", "processes", "ray"):
        rate = p["items"] / p[f"{b}_s"]
        print(f"| {b} | {p[f'{b}_s']:.2f} | {rate:.2f} | "
              f"{p['processes_s'] / p[f'{b}_s']:.2f} | {p[f'{b}_start_s']:.1f} s |")
    print(f"\nload average at end: {' '.join(f'{x:.1f}' for x in os.getloadavg())}")
    if a.quick:
        print("bench/vector_env.py --quick: ran")
    return 0


if __name__ == "__main__":
    sys.exit(main())

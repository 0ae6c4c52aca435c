"""Learning to walk farther than the planned gait: CMA-ES on residual joint targets around it,
trained on `dbot.env.VectorEnv` (N physics robots with their firmware, on Rust threads).

The policy acts as a residual around the plan, as MuJoCo Playground's Go1 policy acts around its
home pose: at each step (one bus cycle, 10 ms) the joint targets are the planned angles at the
gait's phase plus

    residual(phase) = SCALE_RAD * tanh(b + A sin(2 pi phase) + B cos(2 pi phase))

per joint (A, B, b: 22 values each, 66 parameters; all zero is the open-loop gait;
`dbot.vector_pool.residual`), with the
plan's joint torques as the torque feed-forward; both blend in from the resting posture over the
first 0.5 s, as `dbot.sweep.gait_rollout` starts its walks. The fitness of a parameter vector is
the distance its walk covers along world x in one episode (`VectorEnv`'s reward, summed), less
``FALL_PENALTY_M`` if it fell (a fall ends the episode).

Why CMA-ES (pycma, `cma`): it installs with NumPy only (torch, which Stable-Baselines3 and
CleanRL's PPO need, installs here only as its multi-GB CUDA build), suits a few dozen
parameters, is seeded (the run is reproducible) and its state pickles (training resumes). An
episode is deterministic on the physics robot, so each candidate is evaluated once; the
candidates of a generation run side by side on the vector environment's robots.

    .venv/bin/python python/examples/learn_residual.py --out out/learn          # the full run
    .venv/bin/python python/examples/learn_residual.py --out /tmp/l --generations 2 --popsize 4 \\
        --episode-steps 40 --envs 2                                              # a smoke run

Writes to ``--out``: ``policy.npz`` (the best parameters, the plan's settings, the learning
curve), ``cma.pkl`` (the optimiser's state, to resume with ``--resume``) and ``learning_curve.png``
(best and mean episode reward of each generation against environment steps, beside the open-loop
gait's reward).
"""

from __future__ import annotations

import argparse
import pathlib
import pickle
import sys

import numpy as np

import dbot
from dbot.env import VectorEnv
from dbot.vector_pool import FALL_PENALTY_M, SCALE_RAD, Gait, residual, residual_walks

__all__ = ["FALL_PENALTY_M", "SCALE_RAD", "Gait", "residual", "rollouts", "train", "load", "main"]

def rollouts(env: VectorEnv, thetas: np.ndarray, steps: int) -> np.ndarray:
    """Each row of ``thetas`` walked on its own robot (``dbot.vector_pool.residual_walks``, on
    the default plan's gait): its fitness, distance along x less a fall's penalty, m."""
    return np.asarray(residual_walks(env, list(thetas), steps))


def train(
    out: pathlib.Path,
    *,
    envs: int = 2,
    generations: int = 20,
    popsize: int = 8,
    episode_steps: int = 500,
    sigma: float = 0.5,
    seed: int = 1,
    resume: bool = False,
) -> dict[str, np.ndarray]:
    """Trains, writes ``out``/policy.npz, cma.pkl and learning_curve.png; returns the curve."""
    import cma

    out.mkdir(parents=True, exist_ok=True)
    model = dbot.Model.builtin("drosophibot2")
    # One episode is exactly the rollout: truncated after its last step.
    env = VectorEnv(envs, max_episode_steps=episode_steps, torques=True)
    dim = 3 * len(model.servo_joints)
    if resume:
        es = pickle.loads((out / "cma.pkl").read_bytes())
        curve = dict(np.load(out / "policy.npz"))
        steps_done = int(curve["steps"][-1]) if len(curve["steps"]) else 0
        history = {k: list(curve[k]) for k in ("steps", "best", "mean")}
        open_loop = float(curve["open_loop"])
        best = (curve["theta"], float(curve["reward"]))
    else:
        es = cma.CMAEvolutionStrategy(
            np.zeros(dim), sigma, {"popsize": popsize, "seed": seed, "verbose": -9}
        )
        open_loop = float(rollouts(env, np.zeros((1, dim)), episode_steps)[0])
        steps_done = episode_steps
        history = {"steps": [], "best": [], "mean": []}
        best = (np.zeros(dim), open_loop)
    for _ in range(generations):
        candidates = np.asarray(es.ask())
        rewards = rollouts(env, candidates, episode_steps)
        es.tell(list(candidates), list(-rewards))
        steps_done += len(candidates) * episode_steps
        history["steps"].append(steps_done)
        history["best"].append(float(rewards.max()))
        history["mean"].append(float(rewards.mean()))
        if rewards.max() > best[1]:
            best = (candidates[int(rewards.argmax())], float(rewards.max()))
        print(
            f"steps {steps_done:7d}  best {rewards.max():.4f} m  mean {rewards.mean():.4f} m  "
            f"(open loop {open_loop:.4f} m)",
            flush=True,
        )
    env.close()
    curve = {k: np.asarray(v) for k, v in history.items()}
    save(out, best[0], best[1], open_loop, curve, episode_steps)
    (out / "cma.pkl").write_bytes(pickle.dumps(es))
    plot(out / "learning_curve.png", curve, open_loop)
    return {**curve, "open_loop": np.asarray(open_loop), "theta": best[0]}


def save(
    out: pathlib.Path,
    theta: np.ndarray,
    reward: float,
    open_loop: float,
    curve: dict[str, np.ndarray],
    episode_steps: int,
) -> None:
    np.savez(
        out / "policy.npz",
        theta=theta,
        reward=reward,
        open_loop=open_loop,
        episode_steps=episode_steps,
        scale_rad=SCALE_RAD,
        **curve,
    )


def load(path: pathlib.Path) -> dict[str, np.ndarray]:
    """A saved policy: ``theta``, its ``reward``, ``open_loop``, the curve, ``episode_steps``."""
    with np.load(path) as f:
        return {k: f[k] for k in f.files}


def plot(path: pathlib.Path, curve: dict[str, np.ndarray], open_loop: float) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(curve["steps"], curve["best"], "o-", label="best of the generation")
    ax.plot(curve["steps"], curve["mean"], "s--", label="mean of the generation")
    ax.axhline(open_loop, color="k", lw=1, label="open-loop planned gait")
    ax.set_xlabel("environment steps (bus cycles, all robots)")
    ax.set_ylabel("episode reward: distance along x, m\n(less 1 m for a fall)")
    ax.set_title("CMA-ES on residual joint targets around the planned gait")
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=pathlib.Path, default=pathlib.Path("out/learn"))
    ap.add_argument("--envs", type=int, default=2, help="robots stepped side by side")
    ap.add_argument("--generations", type=int, default=20)
    ap.add_argument("--popsize", type=int, default=8)
    ap.add_argument("--episode-steps", type=int, default=500, help="bus cycles per episode")
    ap.add_argument("--sigma", type=float, default=0.5, help="CMA-ES initial step size")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--resume", action="store_true", help="continue from --out's cma.pkl")
    a = ap.parse_args(argv)
    train(
        a.out,
        envs=a.envs,
        generations=a.generations,
        popsize=a.popsize,
        episode_steps=a.episode_steps,
        sigma=a.sigma,
        seed=a.seed,
        resume=a.resume,
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""A central pattern generator walking Drosophibot II in closed loop through `dbot` streaming.

One phase oscillator per leg, all-to-all coupled so that the two tripods (LF, RM, LH) and
(RF, LM, RH) settle in anti-phase, with load feedback from the servos' proprioception that delays
lift-off of a leg that still carries load late in stance. Each oscillator's phase picks its leg's
posture on the planned tripod footpath (`dbot.plan`), and the resulting joint targets are streamed
to the board every bus cycle. The recorded proprioception is saved (NPZ) and plotted (PNG).

Why not sns-toolbox: sns-toolbox 1.5.2 (PyPI) imports torch at module level (`design/neurons.py`,
`backends.py`), and PyPI's Linux torch wheels pull the CUDA runtime packages (gigabytes) - too
heavy for this project's CI, whose only package index is PyPI. The oscillator network here is
the phase-reduced form of the same idea (a half-centre CPG per leg, coupled between legs); see
examples/README.md.

Run (after `bash scripts/setup.d/40-python.sh`):

    .venv/bin/python examples/tripod_cpg.py --port virtual --steps 12 --out out/examples
    .venv/bin/python examples/tripod_cpg.py --port physics --steps 12 --out out/examples  # MuJoCo body
"""

from __future__ import annotations

import argparse
import pathlib
from dataclasses import dataclass, field

import numpy as np

import dbot

#: The two tripods: each swings together, the other stands.
TRIPOD_A = ("LF", "RM", "LH")
TRIPOD_B = ("RF", "LM", "RH")


@dataclass
class TripodCPG:
    """Six coupled phase oscillators (phase in cycles, 0..1; 0 = touch-down, `duty` = lift-off).

    d psi_i / dt = (1 - g lambda_i) / T + K / (2 pi) sum_j sin(2 pi (psi_j - psi_i - Delta_ij))

    with Delta_ij = 0 within a tripod and 1/2 across, K the coupling (1/s), and lambda_i in 0..1 the
    excess load of leg i over its running mean, active only in the last `load_window` of stance
    (load keeps a leg on the ground: the campaniform-sensilla reflex of insect walking models).
    """

    legs: list[str]
    period_s: float
    duty: float
    coupling: float = 2.0
    load_gain: float = 0.3
    load_window: float = 0.2
    phase: np.ndarray = field(default_factory=lambda: np.zeros(6))
    load_mean: np.ndarray = field(default_factory=lambda: np.ones(6))

    def __post_init__(self) -> None:
        group = np.array([0 if leg in TRIPOD_A else 1 for leg in self.legs])
        self.offset = 0.5 * (group[:, None] != group[None, :])

    def step(self, dt: float, load: np.ndarray) -> np.ndarray:
        """Advances the phases by `dt` seconds given each leg's load (any unit); returns them."""
        self.load_mean += 0.02 * (load - self.load_mean)
        excess = np.clip(load / np.maximum(self.load_mean, 1e-9) - 1.0, 0.0, 1.0)
        late_stance = (self.phase > self.duty - self.load_window) & (self.phase < self.duty)
        drive = (1.0 - self.load_gain * excess * late_stance) / self.period_s
        diff = self.phase[None, :] - self.phase[:, None] - self.offset
        pull = self.coupling / (2 * np.pi) * np.sin(2 * np.pi * diff).sum(axis=1)
        self.phase = (self.phase + dt * (drive + pull)) % 1.0
        return self.phase

    def in_stance(self) -> np.ndarray:
        return self.phase < self.duty


class LegMap:
    """Where each leg's servos sit in a setpoint and where its cycle starts in the plan."""

    def __init__(self, plan: dbot.Plan, model: dbot.Model) -> None:
        self.plan = plan
        self.legs = plan.legs
        names = model.servo_joint_names
        self.servo_cols = np.array(model.servo_joints)
        self.leg_servos = [
            np.array([k for k, n in enumerate(names) if n.startswith(leg + "_")]) for leg in self.legs
        ]
        st = plan.stance
        n = plan.slices
        # Touch-down slice of each leg: stance now, swing in the slice before.
        self.touchdown = [
            next(s for s in range(n) if st[s, i] and not st[s - 1, i]) for i in range(len(self.legs))
        ]
        self.angles = plan.angles[:, self.servo_cols]  # [slice, servo joint]

    def targets(self, phase: np.ndarray) -> np.ndarray:
        """Servo joint targets (rad) for the oscillator phases, interpolated between slices."""
        n = self.plan.slices
        out = self.angles[0].copy()
        for i, cols in enumerate(self.leg_servos):
            x = (self.touchdown[i] + phase[i] * n) % n
            s0 = int(np.floor(x))
            s1 = (s0 + 1) % n
            w = x - s0
            out[cols] = (1 - w) * self.angles[s0, cols] + w * self.angles[s1, cols]
        return out

    def stance_from_angles(self, present: np.ndarray, window: int = 6) -> np.ndarray:
        """Stance per leg read off measured joint angles [record, servo joint]: each leg's
        position on its planned cycle is tracked as the plan slice nearest to its measured
        posture, searched from the previous slice a few slices forward (legs only move forward
        through their cycle, and a front leg's early swing passes close to its late-stance
        posture in joint space, so a global search flickers); the slice's stance flag is the
        leg's stance. Returns bool [record, leg]."""
        n = self.plan.slices
        out = np.zeros((present.shape[0], len(self.legs)), dtype=bool)
        for i, cols in enumerate(self.leg_servos):
            ref = self.angles[:, cols]
            s = int(np.argmin(((present[0, cols] - ref) ** 2).sum(axis=1)))
            for r in range(present.shape[0]):
                near = (s + np.arange(0, window + 1)) % n
                d = ((present[r, cols] - ref[near]) ** 2).sum(axis=1)
                s = int(near[np.argmin(d)])
                out[r, i] = self.plan.stance[s, i]
        return out

    def leg_load(self, load_raw: np.ndarray) -> np.ndarray:
        """Mean |load register| of each leg's servos (raw units, as read)."""
        return np.array([np.abs(load_raw[cols]).mean() for cols in self.leg_servos])


def stand(board: dbot.Board, plan: dbot.Plan, slot: int = 0) -> None:
    """Uploads `plan` and plays one step so the robot stands in its posture (streaming starts
    only from standing)."""
    board.upload_plan(slot, plan, name="tripod")
    board.play(slot, steps=1)
    for _ in range(100):
        board.wait(0.1)
        if board.status()["state"] == "Standing":
            return
    raise RuntimeError(f"the robot did not stand after one step: {board.status()}")


def walk(
    board: dbot.Board,
    model: dbot.Model,
    plan: dbot.Plan,
    steps: int,
    initial_phase: np.ndarray,
    blend_s: float = 0.5,
) -> dict[str, np.ndarray]:
    """Streams the CPG's targets until every leg has lifted off `steps` times; returns the
    recording: proprioception arrays plus the CPG's `phase` and `cpg_stance` per record."""
    legs = LegMap(plan, model)
    cpg = TripodCPG(list(plan.legs), plan.period_s, plan.duty, phase=initial_phase.copy())
    stand(board, plan)
    board.enter_streaming(timeout_cycles=5, feedback_every=1)
    first = board.next_proprioception(timeout_s=0.1)
    if first is None:
        raise RuntimeError("no proprioception after entering streaming")
    start_pose = first["present_rad"][0]
    t0 = float(first["time_s"][0])
    last_t = t0
    records: list[dict[str, np.ndarray]] = []
    phases, cpg_stance = [], []
    liftoffs = np.zeros(len(plan.legs), dtype=int)
    was_stance = cpg.in_stance()
    load = legs.leg_load(first["load_raw"][0])
    while liftoffs.min() < steps:
        targets = legs.targets(cpg.phase)
        # Blend from the standing posture so nothing jumps when the stream starts.
        w = min(1.0, (last_t - t0) / blend_s)
        board.send_setpoint((1 - w) * start_pose + w * targets)
        rec = board.next_proprioception(timeout_s=0.1)
        if rec is None:
            raise RuntimeError(f"proprioception stopped: {board.status()}")
        t = float(rec["time_s"][0])
        load = legs.leg_load(rec["load_raw"][0])
        cpg.step(t - last_t, load)
        last_t = t
        now_stance = cpg.in_stance()
        liftoffs += was_stance & ~now_stance
        was_stance = now_stance
        records.append(rec)
        phases.append(cpg.phase.copy())
        cpg_stance.append(now_stance)
    board.leave_streaming()
    out = {k: np.concatenate([r[k] for r in records]) for k in records[0]}
    out["phase"] = np.array(phases)
    out["cpg_stance"] = np.array(cpg_stance)
    out["stance"] = legs.stance_from_angles(out["present_rad"])
    out["liftoffs"] = liftoffs
    return out


def tripod_report(stance: np.ndarray, legs: list[str]) -> dict[str, float]:
    """How tripod-like a stance pattern [record, leg] is: the fraction of records in which the
    legs of each tripod agree, the fraction in which legs of both tripods swing at once, and the
    phase (in cycles) of each leg's touch-downs relative to LF's."""
    idx = {leg: i for i, leg in enumerate(legs)}
    a = stance[:, [idx[x] for x in TRIPOD_A]]
    b = stance[:, [idx[x] for x in TRIPOD_B]]
    agree = float(np.mean(np.all(a == a[:, :1], axis=1) & np.all(b == b[:, :1], axis=1)))
    both_swing = float(np.mean((~a).any(axis=1) & (~b).any(axis=1)))
    down = {leg: np.flatnonzero(stance[1:, i] & ~stance[:-1, i]) + 1 for leg, i in idx.items()}
    ref = down["LF"]
    report = {"agree": agree, "both_swing": both_swing}
    if len(ref) >= 2:
        period = float(np.median(np.diff(ref)))
        for leg, t in down.items():
            lag = [((t[np.argmin(np.abs(t - r))] - r) / period) % 1.0 for r in ref if len(t)]
            # Circular mean of the lags, in 0..1 cycles.
            z = np.mean(np.exp(2j * np.pi * np.array(lag)))
            report[f"phase_{leg}"] = float((np.angle(z) / (2 * np.pi)) % 1.0)
    return report


def plot(rec: dict[str, np.ndarray], legs: list[str], names: list[str], path: pathlib.Path) -> None:
    """Footfall diagram (stance read off the servos), one leg's joints, per-leg load."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = rec["time_s"] - rec["time_s"][0]
    fig, ax = plt.subplots(3, 1, figsize=(10, 8), sharex=True)
    for i, leg in enumerate(legs):
        on = rec["stance"][:, i]
        ax[0].fill_between(t, i - 0.4, i + 0.4, where=on, color="k", step="mid", linewidth=0)
    ax[0].set_yticks(range(len(legs)), legs)
    ax[0].set_title("stance (black) read off the measured joint angles")
    cols = [k for k, n in enumerate(names) if n.startswith("LF_")]
    for k in cols:
        ax[1].plot(t, rec["present_rad"][:, k], label=names[k])
        ax[1].plot(t, rec["commanded_rad"][:, k], "k:", linewidth=0.6)
    ax[1].set_ylabel("LF joints, rad")
    ax[1].legend(fontsize=7, ncol=4)
    for i, leg in enumerate(legs):
        legcols = [k for k, n in enumerate(names) if n.startswith(leg + "_")]
        ax[2].plot(t, np.abs(rec["load_raw"][:, legcols]).mean(axis=1), label=leg)
    ax[2].set_ylabel("mean |load register|, raw")
    ax[2].set_xlabel("time, s (board clock)")
    ax[2].legend(fontsize=7, ncol=6)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100)
    plt.close(fig)


#: Start far from a tripod (LF and RF almost in phase) so the coupling has work to do.
INITIAL_PHASE = np.array([0.0, 0.1, 0.25, 0.05, 0.3, 0.15])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--port", default="virtual", help="board port, pty path, `virtual` or `physics[:SCENE]`")
    ap.add_argument("--steps", type=int, default=12, help="steps per leg to walk")
    ap.add_argument("--out", type=pathlib.Path, default=pathlib.Path("out/examples"))
    args = ap.parse_args()
    model = dbot.Model.builtin("drosophibot2")
    plan = dbot.plan(model, slices=50)
    board = dbot.Board.open(args.port)
    rec = walk(board, model, plan, args.steps, INITIAL_PHASE)
    args.out.mkdir(parents=True, exist_ok=True)
    np.savez(args.out / "tripod_cpg.npz", **rec)
    plot(rec, list(plan.legs), model.servo_joint_names, args.out / "tripod_cpg.png")
    settled = rec["stance"][len(rec["stance"]) // 3 :]
    print(f"walked {rec['liftoffs'].min()} steps per leg; tripod report (last two thirds):")
    for k, v in tripod_report(settled, list(plan.legs)).items():
        print(f"  {k}: {v:.3f}")
    print(f"wrote {args.out / 'tripod_cpg.npz'} and {args.out / 'tripod_cpg.png'}")


if __name__ == "__main__":
    main()

"""A synthetic nervous system (SNS) walking Drosophibot II through `dbot.env.DbotEnv`, closed loop.

The network is the lab's kind (Szczecinski, Hunt and Quinn 2017, "A functional subnetwork
approach to designing synthetic nervous systems"): non-spiking leaky-integrator neurons,

    C dU/dt = -G_m U + sum_j g_j(U_j) (E_j - U) + I_app + I_sensor,
    g_j(U_j) = g_max,j * clip(U_j / R, 0, 1)         (graded synapse, R = 20 mV),

U the membrane voltage above rest (mV), C in nF, conductances in uS, currents in nA. Per leg:

* a rhythm generator: a swing (SW) and a stance (ST) neuron inhibiting each other (a half-centre,
  winner-take-all), both with the same tonic drive;
* three sensory neurons: AEP (the leg has reached the end of its swing), PEP (the end of its
  stance) and LOAD (the leg is loaded more than its running mean). AEP excites ST and inhibits
  SW; PEP excites SW and inhibits ST; LOAD excites ST (a loaded leg does not lift; on an incline
  the hind legs push longer);
* between legs, each SW inhibits the SW of its neighbours (ipsilateral and contralateral), so
  neighbours do not swing together (Cruse's first coordination rule); a tripod emerges.

What LOAD senses: where the observation carries the strain gauges (the physics robot:
``DbotEnv.has_strain``), the leg's six gauges at the insect's trochanteral and femoral
campaniform-sensilla fields (trochanter axial, transverse, 45 deg; femur +45, -45 deg, axial),
as the insect's CS signal load: the RMS of their readings (microstrain), over its running mean.
The cuticle strains while the leg carries the body and hardly in swing, so this is the CS's
load signal. Without strain (a board with no strain board beside it) LOAD falls back on the
leg's servo load registers (mean |load_raw|), over their running mean. ``run`` says which it
used (``feedback``: ``strain`` or ``load``).

The motor layer moves each leg along its planned footpath (`dbot.plan`'s joint angles over one
step cycle, with the plan's joint torques as the torque feed-forward of the setpoint): its
position on the path advances at the plan's pace scaled by the active RG neuron's output, through
stance while ST wins and through swing while SW wins, and waits at the path's end (AEP or PEP)
until the network switches.

Why NumPy and not sns-toolbox: sns-toolbox (PyPI) imports torch at module level, and PyPI's
Linux torch wheels pull the CUDA runtime (gigabytes) - too heavy for this project's CI. The
network here is small (30 neurons) and written out in full.

The same script runs on the physics robot and on a board (the RP2040 emulator's pty, a real
board): the controller reads only the observation (strain where there is strain, else the load
registers).

    .venv/bin/python python/examples/sns_walk.py --port physics --cycles 4 --out out/sns
    .venv/bin/python python/examples/sns_walk.py --port physics:incline:5 --cycles 4 --out out/sns
"""

from __future__ import annotations

import argparse
import pathlib
from dataclasses import dataclass

import numpy as np

import dbot
from dbot.env import DbotEnv

#: Legs in the plan's order and their neighbours (ipsilateral and contralateral).
NEIGHBOURS = {
    "LF": ("LM", "RF"),
    "LM": ("LF", "LH", "RM"),
    "LH": ("LM", "RH"),
    "RF": ("RM", "LF"),
    "RM": ("RF", "RH", "LM"),
    "RH": ("RM", "LH"),
}
#: Neurons of one leg, in the network's order.
LEG_NEURONS = ("SW", "ST", "AEP", "PEP", "LOAD")
#: Tripods (for the starting positions): A starts its swing, B stands in mid-stance.
TRIPOD_A = ("LF", "RM", "LH")

R_MV = 20.0  # the operating range of every neuron, mV
E_EX_MV = 134.0  # excitatory reversal above rest, mV (sodium-like)
E_IN_MV = -40.0  # inhibitory reversal below rest, mV


@dataclass
class Network:
    """Leaky integrators U (mV above rest) with graded synapses G[post, pre], E[post, pre]."""

    c_nf: np.ndarray
    gm_us: np.ndarray
    i_app_na: np.ndarray
    g_max_us: np.ndarray
    e_mv: np.ndarray
    u_mv: np.ndarray

    def step(self, dt_s: float, i_in_na: np.ndarray) -> np.ndarray:
        """One step of `dt_s` under input currents; semi-implicit (the conductances implicit),
        so it is stable for any step. Returns U."""
        act = np.clip(self.u_mv / R_MV, 0.0, 1.0)
        g = self.g_max_us * act[None, :]
        g_sum = g.sum(axis=1)
        drive = (g * self.e_mv).sum(axis=1) + self.i_app_na + i_in_na
        dt_ms = dt_s * 1e3
        self.u_mv = (self.u_mv + dt_ms / self.c_nf * drive) / (
            1.0 + dt_ms / self.c_nf * (self.gm_us + g_sum)
        )
        return self.u_mv

    def activity(self) -> np.ndarray:
        return np.clip(self.u_mv / R_MV, 0.0, 1.0)


def build_network(legs: list[str], gains: dict[str, float] | None = None) -> Network:
    """The network for `legs`; `gains` overrides synapse strengths (uS): `rg` (mutual
    inhibition in a rhythm generator), `aep`, `pep`, `load`, `neighbour`."""
    g = {"rg": 2.0, "aep": 4.0, "pep": 4.0, "load": 1.5, "neighbour": 3.0}
    g.update(gains or {})
    n = len(legs) * len(LEG_NEURONS)
    idx = {(leg, k): i * len(LEG_NEURONS) + j for i, leg in enumerate(legs) for j, k in enumerate(LEG_NEURONS)}
    G = np.zeros((n, n))
    E = np.zeros((n, n))

    def syn(post: tuple[str, str], pre: tuple[str, str], gmax: float, e: float) -> None:
        G[idx[post], idx[pre]] = gmax
        E[idx[post], idx[pre]] = e

    for leg in legs:
        syn((leg, "SW"), (leg, "ST"), g["rg"], E_IN_MV)
        syn((leg, "ST"), (leg, "SW"), g["rg"], E_IN_MV)
        syn((leg, "ST"), (leg, "AEP"), g["aep"], E_EX_MV)
        syn((leg, "SW"), (leg, "AEP"), g["aep"], E_IN_MV)
        syn((leg, "SW"), (leg, "PEP"), g["pep"], E_EX_MV)
        syn((leg, "ST"), (leg, "PEP"), g["pep"], E_IN_MV)
        syn((leg, "ST"), (leg, "LOAD"), g["load"], E_EX_MV)
        for other in NEIGHBOURS[leg]:
            if other in legs:
                syn((leg, "SW"), (other, "SW"), g["neighbour"], E_IN_MV)
    i_app = np.zeros(n)
    for leg in legs:
        # Tonic drive of the half-centre: alone, each would sit at R (I / G_m = 20 mV).
        i_app[idx[(leg, "SW")]] = R_MV
        i_app[idx[(leg, "ST")]] = R_MV
    c = np.full(n, 5.0)  # nF: tau = C / G_m = 5 ms for sensors...
    c[[idx[(leg, k)] for leg in legs for k in ("SW", "ST")]] = 50.0  # ... 50 ms for the RG
    return Network(c, np.ones(n), i_app, G, E, np.zeros(n))


class SNSController:
    """The network, its sensors and the motor layer for one plan; `act(obs, dt)` -> action."""

    def __init__(self, model: dbot.Model, plan: dbot.Plan, gains: dict[str, float] | None = None,
                 load_tau_s: float = 2.0, end_window: float = 0.04,
                 strain_names: list[str] | None = None) -> None:
        """``strain_names``: the observation's gauges (``DbotEnv.strain_names``); given and not
        empty, LOAD senses strain, else the servo load registers."""
        self.plan = plan
        self.legs = list(plan.legs)
        self.duty = plan.duty
        self.period_s = plan.period_s
        self.end_window = end_window
        self.load_tau_s = load_tau_s
        names = model.servo_joint_names
        cols = np.array(model.servo_joints)
        self.leg_servos = [np.array([k for k, nm in enumerate(names) if nm.startswith(leg + "_")]) for leg in self.legs]
        st = plan.stance
        n = plan.slices
        self.touchdown = [next(s for s in range(n) if st[s, i] and not st[s - 1, i]) for i in range(len(self.legs))]
        self.angles = plan.angles[:, cols]
        self.torques = plan.torques[:, cols]
        self.stall = np.asarray(model.servo_stall_torques_nm)
        self.net = build_network(self.legs, gains)
        self.k = len(LEG_NEURONS)
        # Leg position on its cycle (0 = touch-down, duty = lift-off, 1 = the next touch-down).
        self.x = np.array([self.duty if leg in TRIPOD_A else self.duty - 0.5 for leg in self.legs])
        self.x = np.clip(self.x, 0.0, self.duty)
        # Tripod A starts its swing, tripod B stands in mid-stance.
        self.swinging = np.array([leg in TRIPOD_A for leg in self.legs])
        u = self.net.u_mv
        for i in range(len(self.legs)):
            u[self._neuron(i, "SW" if self.swinging[i] else "ST")] = R_MV
        self.load_mean: np.ndarray | None = None
        names = list(strain_names or [])
        #: Each leg's gauges (columns of ``strain_microstrain``), or None: the load fallback.
        self.leg_gauges = (
            [np.array([k for k, g in enumerate(names) if g.startswith(leg + "_")]) for leg in self.legs]
            if names
            else None
        )
        if self.leg_gauges is not None:
            missing = [leg for leg, g in zip(self.legs, self.leg_gauges, strict=True) if g.size == 0]
            if missing:
                raise ValueError(f"strain_names has no gauge of leg {', '.join(missing)}")
        self.feedback = "strain" if self.leg_gauges is not None else "load"

    def _neuron(self, leg: int, name: str) -> int:
        return leg * self.k + LEG_NEURONS.index(name)

    def leg_load(self, obs: dict[str, np.ndarray]) -> np.ndarray:
        """What LOAD senses per leg: the RMS of the leg's gauges (microstrain) with strain, else
        the mean |load_raw| of its servos."""
        if self.leg_gauges is not None:
            s = obs["strain_microstrain"]
            return np.array([np.sqrt(np.mean(s[g] ** 2)) for g in self.leg_gauges])
        return np.array([np.abs(obs["load_raw"][c]).mean() for c in self.leg_servos])

    def _sensors(self, obs: dict[str, np.ndarray], dt: float) -> np.ndarray:
        """Sensor currents (nA): AEP and PEP ramp to R x G_m over the last `end_window` of swing
        and stance; LOAD is the leg's excess load (strain or servo load, `leg_load`) over its
        running mean, in R per 100 %."""
        load = self.leg_load(obs)
        if self.load_mean is None:
            self.load_mean = np.maximum(load, 1.0)
        self.load_mean += dt / self.load_tau_s * (load - self.load_mean)
        excess = np.clip(load / np.maximum(self.load_mean, 1.0) - 1.0, 0.0, 1.0)
        w = self.end_window
        aep = np.where(self.swinging, np.clip((self.x - (1.0 - w)) / w, 0.0, 1.0), 0.0)
        pep = np.where(~self.swinging, np.clip((self.x - (self.duty - w)) / w, 0.0, 1.0), 0.0)
        i = np.zeros(len(self.net.u_mv))
        for leg in range(len(self.legs)):
            i[self._neuron(leg, "AEP")] = R_MV * aep[leg]
            i[self._neuron(leg, "PEP")] = R_MV * pep[leg]
            i[self._neuron(leg, "LOAD")] = R_MV * excess[leg]
        return i

    def step(self, obs: dict[str, np.ndarray], dt: float) -> None:
        """Senses `obs`, advances the network and the legs' positions by `dt` seconds."""
        self.net.step(dt, self._sensors(obs, dt))
        a = self.net.activity()
        for leg in range(len(self.legs)):
            sw, st = a[self._neuron(leg, "SW")], a[self._neuron(leg, "ST")]
            if sw > st and not self.swinging[leg]:
                self.swinging[leg] = True
            elif st > sw and self.swinging[leg]:
                self.swinging[leg] = False
                self.x[leg] = 0.0  # touch-down: the next cycle
            rate = (sw if self.swinging[leg] else st) / self.period_s
            end = 1.0 if self.swinging[leg] else self.duty
            self.x[leg] = min(end, self.x[leg] + dt * rate)

    def targets(self) -> tuple[np.ndarray, np.ndarray]:
        """Joint targets (rad) and torque feed-forward (N m) at the legs' positions."""
        n = self.plan.slices
        q = self.angles[0].copy()
        tau = np.zeros_like(q)
        for i, cols in enumerate(self.leg_servos):
            s = (self.touchdown[i] + self.x[i] * n) % n
            s0 = int(np.floor(s))
            s1, w = (s0 + 1) % n, s - s0
            q[cols] = (1 - w) * self.angles[s0, cols] + w * self.angles[s1, cols]
            tau[cols] = (1 - w) * self.torques[s0, cols] + w * self.torques[s1, cols]
        return q, np.clip(tau, -self.stall, self.stall)

    def in_stance(self) -> np.ndarray:
        return ~self.swinging


def run(port: str, cycles: float, gains: dict[str, float] | None = None, max_steps: int | None = None,
        blend_s: float = 0.5, seed: int = 0, feedback: str = "auto") -> dict[str, np.ndarray]:
    """Walks `cycles` planned step periods on `port`; returns the run's record: time, neuron
    activity [step, neuron], controller stance [step, leg], measured foot contact (physics only),
    thorax x (physics only), what LOAD sensed (`feedback`: `strain` where the observation has
    it, else `load`) and whether it fell or the firmware faulted. `feedback="load"` senses the
    servo load even where there is strain (for comparison)."""
    if feedback not in ("auto", "load"):
        raise ValueError(f"feedback = {feedback!r}: give 'auto' (strain where there is strain) or 'load'")
    model = dbot.Model.builtin("drosophibot2")
    # The footpaths are planned for the scene where the planner can (flat, an incline: there
    # its torques carry the tilted weight); for other ground (blocks) the flat plan.
    scene = port.split(":", 1)[1] if port.startswith("physics:") else "flat"
    terrain = scene if scene.startswith("incline:") else "flat"
    plan = dbot.plan(model, slices=50, terrain=terrain)
    dt = 0.01  # one bus cycle at the firmware's default 100 Hz
    steps = int(round(cycles * plan.period_s / dt))
    if max_steps is not None:
        steps = min(steps, max_steps)
    env = DbotEnv(port, model=model, gait=plan, torques=True, max_episode_steps=steps + 1)
    strain = env.strain_names if feedback == "auto" else None
    ctl = SNSController(model, plan, gains, strain_names=strain)
    obs, info = env.reset(seed=seed)
    rest = env.rest_rad
    rec: dict[str, list] = {"time_s": [], "activity": [], "stance": [], "contact": [], "x_m": []}
    ended = "no"
    for k in range(steps):
        ctl.step(obs, dt)
        q, tau = ctl.targets()
        w = min(1.0, k * dt / blend_s)  # blend from the resting posture: nothing jumps
        action = {"angles_rad": (1 - w) * rest + w * q, "torques_nm": w * tau}
        obs, _, terminated, truncated, info = env.step(action)
        rec["time_s"].append(info["time_s"])
        rec["activity"].append(ctl.net.activity().copy())
        rec["stance"].append(ctl.in_stance().copy())
        if "body" in info:
            rec["contact"].append(np.asarray(info["body"]["foot_contact"], dtype=bool))
            rec["x_m"].append(float(info["body"]["thorax_position_m"][0]))
        if terminated:
            ended = "fault" if info["state"] == "Fault" else "fall"
            break
    env.close()
    out = {k: np.asarray(v) for k, v in rec.items()}
    out["ended"] = np.asarray(ended)
    out["feedback"] = np.asarray(ctl.feedback)
    out["legs"] = np.asarray(ctl.legs)
    out["neurons"] = np.asarray([f"{leg}_{n}" for leg in ctl.legs for n in LEG_NEURONS])
    return out


def plot(rec: dict[str, np.ndarray], path: pathlib.Path) -> None:
    """Each leg's rhythm-generator neurons (SW, ST) and load neuron beside its stance: the
    controller's (grey band) and, on the physics robot, the measured foot contact (black bar)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    legs = list(rec["legs"])
    t = rec["time_s"] - rec["time_s"][0]
    fig, ax = plt.subplots(len(legs), 1, figsize=(10, 1.6 * len(legs)), sharex=True)
    for i, leg in enumerate(legs):
        a = ax[i]
        a.fill_between(t, 0, 1.05, where=rec["stance"][:, i], color="0.85", step="mid", linewidth=0,
                       label="controller stance")
        if rec["contact"].size:
            a.fill_between(t, 1.1, 1.25, where=rec["contact"][:, i], color="k", step="mid",
                           linewidth=0, label="foot contact (measured)")
        for name, style in (("SW", "C0-"), ("ST", "C1-"), ("LOAD", "C2:")):
            j = list(rec["neurons"]).index(f"{leg}_{name}")
            label = f"LOAD ({rec['feedback']})" if name == "LOAD" else name
            a.plot(t, rec["activity"][:, j], style, linewidth=1, label=label)
        a.set_ylabel(f"{leg}\nU / R")
        a.set_ylim(0, 1.3)
    ax[0].legend(fontsize=7, ncol=5, loc="upper right")
    ax[-1].set_xlabel("time, s")
    fig.suptitle("SNS walk: neuron activity (U / R) beside stance")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--port", default="physics", help="`physics[:SCENE]`, a pty path or a board")
    ap.add_argument("--cycles", type=float, default=4.0, help="planned step periods to walk")
    ap.add_argument("--out", type=pathlib.Path, default=pathlib.Path("out/sns"))
    ap.add_argument("--feedback", default="auto", choices=["auto", "load"],
                    help="what LOAD senses: strain where the port streams it (auto), or servo load")
    args = ap.parse_args()
    rec = run(args.port, args.cycles, feedback=args.feedback)
    args.out.mkdir(parents=True, exist_ok=True)
    plot(rec, args.out / "sns_walk.png")
    if rec["x_m"].size:
        print(f"walked {rec['x_m'][-1] - rec['x_m'][0]:.3f} m in {rec['time_s'][-1] - rec['time_s'][0]:.1f} s; fell or faulted: {rec['ended']}; LOAD sensed {rec['feedback']}")
    print(f"wrote {args.out / 'sns_walk.png'}")


if __name__ == "__main__":
    main()

"""A gait study over many rollouts: stride and swing time -> distance, slip, energy, tracking
error and falls of the physics robot with the firmware in the loop, run on Ray (a local cluster,
or any cluster by `--address`), written as a tidy table (CSV and Markdown) and a Pareto plot of
distance against energy (the servos' mechanical work, from an ESTIMATE of their torque from the
load registers: `dbot.sweep.mechanical_energy_j`).

    .venv/bin/python python/examples/sweep_gaits.py --out out/sweep                     # local Ray
    .venv/bin/python python/examples/sweep_gaits.py --address HEAD:6379 --out out/sweep # a cluster
    .venv/bin/python python/examples/sweep_gaits.py --backend processes --out out/sweep
"""

from __future__ import annotations

import argparse
import csv
import pathlib

import numpy as np

from dbot.sweep import gait_rollout, grid, pareto, plot_pareto, sweep, table


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--backend", default="ray", choices=["serial", "processes", "ray"])
    ap.add_argument("--address", default=None, help="a Ray cluster's address (default: start one here)")
    ap.add_argument("--cycles", type=float, default=2.0, help="planned step periods per rollout")
    ap.add_argument("--out", type=pathlib.Path, default=pathlib.Path("out/sweep"))
    args = ap.parse_args()
    points = grid(
        translation_m=[round(float(x), 3) for x in np.linspace(0.03, 0.10, 8)],
        swing_s=[0.8, 1.0, 1.2],
        cycles=[args.cycles],
    )
    rows = sweep(gait_rollout, points, backend=args.backend, address=args.address)
    args.out.mkdir(parents=True, exist_ok=True)
    with open(args.out / "sweep.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    (args.out / "sweep.md").write_text(table(rows) + "\n")
    front = plot_pareto(rows, "distance_m", "energy_j", str(args.out / "pareto.png"))
    print(table([rows[i] for i in front]))
    print(f"{len(rows)} rollouts, {sum(r['fell'] for r in rows)} fell; the Pareto front above; "
          f"wrote {args.out}/sweep.csv, sweep.md, pareto.png")


if __name__ == "__main__":
    main()

"""The demo's walk figures from a walk the user runs themselves (`dbot.physics_walk` on the plan
directory `dbot demo` wrote, then `dbot.walk_figures`), against the numbers `dbot demo` prints for
its own forward walk. Both walk the same step table on a fresh physics robot, and the physics
robot is deterministic, so every printed digit must agree: the lines are rebuilt here from the
Python figures with the demo's formats and compared with summary.txt line by line.

Needs the CLI binary: `cargo build -p dbot` (scripts/test.sh builds it before pytest), or
`DBOT_BIN`."""

from __future__ import annotations

import math
import pathlib
import subprocess

import dbot
from dbot_cli import dbot_cli

STEPS = 2


def section(lines: list[str], head: str) -> list[str]:
    """The indented lines under the first line starting with `head`."""
    start = next(i for i, line in enumerate(lines) if line.startswith(head))
    out = []
    for line in lines[start + 1 :]:
        if not line.startswith("  "):
            break
        out.append(line)
    return out


def r2_text(r2: float | None) -> str:
    return "n/a (no variation)" if r2 is None else f"{r2:.2f}"


def test_walk_figures_equal_the_demos_forward_walk(tmp_path: pathlib.Path) -> None:
    demo = tmp_path / "demo"
    run = subprocess.run(
        [str(dbot_cli()), "demo", "--steps", str(STEPS), "--out", str(demo)],
        capture_output=True,
        text=True,
        timeout=1800,
    )
    assert run.returncode == 0, run.stderr
    summary = (demo / "summary.txt").read_text().splitlines()

    walk = dbot.physics_walk(str(demo / "plan"), STEPS, str(tmp_path / "mine"))
    f = dbot.walk_figures(walk)

    # Body: distance, heading, height, tilt, slip (print_body's formats).
    body = section(summary, "body forward ")
    assert body[0] == (
        f"  distance {f['distance_per_step_m']:.4f} m per step, planned "
        f"{f['planned_per_step_m']:.4f} m ({f['distance_off_percent']:+.1f} %; the feet's stroke is "
        f"{f['stroke_m']:.3f} m); lateral {f['lateral_m']:+.4f} m"
    )
    assert body[1] == (
        f"  heading drift {math.degrees(f['heading_rad']):+.2f} deg; thorax height "
        f"{f['height_start_m'] * 1e3:.1f} mm at the start, {f['height_min_m'] * 1e3:.1f} mm lowest, "
        f"{f['height_end_m'] * 1e3:.1f} mm at the end (plan: constant); tilt up to "
        f"{math.degrees(f['tilt_max_rad']):.2f} deg (plan: 0)"
    )
    slip = ", ".join(f"{leg} {m * 1e3:.1f}" for leg, m in f["slip_m"].items())
    assert body[2] == f"  slip while loaded, mm: {slip}"
    # The distance is the body's own: the plan's travel per step is the thorax speed times the
    # period (servo-safe preset: 0.085 m stroke over 1.5 s of stance, 2.5 s per step = 0.1417 m).
    assert abs(f["planned_per_step_m"] - 0.085 / 1.5 * 2.5) < 1e-9

    # Tracking error per leg (print_tracking's formats).
    tracking = section(summary, "tracking error forward ")
    mine = [
        f"  {leg}: RMS {t['rms_rad']:.4f} rad ({math.degrees(t['rms_rad']):.2f} deg), max "
        f"{t['max_abs_rad']:.4f} rad over {t['joints']} joints"
        for leg, t in f["tracking"].items()
    ]
    assert tracking == mine

    # Servo loads against the planned torques (print_fits' formats, six joints a line).
    fits = section(summary, "model vs simulation forward ")
    loads = [
        f"{name} {r2_text(l['r2'])} ({l['rms_nm']:.2f} N m)" for name, l in f["loads"].items()
    ]
    lines = ["    " + ", ".join(loads[i : i + 6]) for i in range(0, len(loads), 6)]
    start = fits.index(
        "  servo load (ESTIMATE from Present Load) vs planned torque per joint, R^2 (RMS difference):"
    )
    assert fits[start + 1 : start + 1 + len(lines)] == lines
    assert len(f["loads"]) == 22

"""Plan directories written by the `dbot` CLI, read through the bindings (`dbot.read_plan_dir`):
the numbers are the files' own (checked against joints.csv parsed here with Python's csv module),
the timing obeys table 1 of the paper, and the step table is byte for byte what `dbot table` writes.

Needs the CLI binary: `cargo build -p dbot` (scripts/test.sh builds it before pytest), or
`DBOT_BIN`."""

from __future__ import annotations

import csv
import json
import math
import pathlib

import numpy as np
import pytest

import dbot
from dbot_cli import dbot_cli, run



@pytest.fixture(scope="module")
def walk(tmp_path_factory: pytest.TempPathFactory) -> pathlib.Path:
    """A plan directory of the built-in robot's tripod gait (the default `servo-safe` preset: table 1
    at a 1.0 s swing, 2.5 s per step; 40 slices), with dynamics."""
    d = tmp_path_factory.mktemp("plans")
    run("plan", "--model", "drosophibot2", "--slices", "40", "--out", "walk", cwd=d)
    return d / "walk"


def test_plan_dir_numbers_are_the_files(walk: pathlib.Path) -> None:
    p = dbot.read_plan_dir(walk)
    assert p.format_version == 1
    assert p.table_name == "walk"
    n_j = len(p.joint_names)
    assert p.angles.shape == (40, n_j)
    assert p.torques is not None and p.torques.shape == (40, n_j)
    assert p.stance.shape == (40, 6)
    # joints.csv parsed independently: one row per slice and joint, in joint order.
    with open(walk / "joints.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 40 * n_j
    angles = np.array([float(r["angle_rad"]) for r in rows]).reshape(40, n_j)
    torques = np.array([float(r["torque_nm"]) for r in rows]).reshape(40, n_j)
    assert np.array_equal(p.angles, angles)
    assert np.array_equal(p.torques, torques)
    # T = T_sw / (1 - duty) = 1.0 / 0.4 s (servo-safe: table 1 at a 1.0 s swing); each leg stands 0.6 * 40 = 24 slices (+-1).
    assert math.isclose(p.period_s, 2.5, rel_tol=1e-12)
    assert math.isclose(p.duty, 0.6, rel_tol=1e-12)
    assert np.all(np.abs(p.stance.sum(axis=0) - 24) <= 1)
    # The planner from Python plans the same gait: the file holds its angles to 10 significant
    # digits (planner::number), so they agree to 1e-9 rad (angles are below 4 rad).
    fresh = dbot.plan(p.model, slices=40)
    assert np.allclose(p.angles, fresh.angles, rtol=0, atol=1e-9)
    # ... from the same default preset as the CLI (one constant, planner::gait::DEFAULT_PRESET).
    assert math.isclose(fresh.period_s, p.period_s, rel_tol=1e-12)


def test_step_table_is_the_cli_table(walk: pathlib.Path) -> None:
    out = walk.parent / "walk.dbgt"
    # This test is about the format: --allow-infeasible keeps it so whatever the plan's speeds.
    run("table", "--plan", str(walk), "--out", str(out), "--allow-infeasible", cwd=walk.parent)
    table = dbot.read_plan_dir(walk).step_table()
    assert table == out.read_bytes()
    # The gait name sits in the 40-byte table header (protocol crate, NUL-padded UTF-8).
    assert b"walk" in table[:40]
    named = dbot.read_plan_dir(walk).step_table("other")
    assert named != table and b"other" in named[:40]


def test_foreign_or_old_directory_names_the_version_and_file(
    walk: pathlib.Path, tmp_path: pathlib.Path
) -> None:
    old = tmp_path / "old"
    old.mkdir()
    text = json.loads((walk / "plan.json").read_text())
    del text["format_version"]
    (old / "plan.json").write_text(json.dumps(text))
    with pytest.raises(ValueError, match=r"old/plan\.json.*format_version"):
        dbot.read_plan_dir(old)
    text["format_version"] = 99
    (old / "plan.json").write_text(json.dumps(text))
    with pytest.raises(ValueError, match=r"plan\.json: plan directory format_version 99"):
        dbot.read_plan_dir(old)

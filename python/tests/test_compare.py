"""``dbot.compare`` is ``dbot compare``: the same rows for a trial against the plan it walked (the
CLI's compare.csv, parsed here with Python's csv module, read to its printed three decimals), and a
trial against itself has R^2 = 1 for every DoF (a series regressed on itself).

Needs the CLI binary: `cargo build -p dbot` (scripts/test.sh builds it before pytest)."""

from __future__ import annotations

import pathlib

import pytest

import dbot
from dbot_cli import csv_rows, record_trial, run


def test_compare_from_python_gives_the_cli_rows(tmp_path: pathlib.Path) -> None:
    record_trial(tmp_path, "t", "virtual", 3, "--plan", "p")
    run("compare", "p", "trials/t", "--out", "by-cli", cwd=tmp_path)
    cli_rows = csv_rows(tmp_path / "by-cli" / "compare.csv")
    rows = dbot.compare(tmp_path / "p", tmp_path / "trials" / "t", tmp_path / "by-python")
    assert len(rows) == len(cli_rows) >= 18
    for py_row, cli_row in zip(rows, cli_rows):
        assert (py_row["leg"], py_row["dof"], py_row["summed_in"]) == (
            cli_row["leg"], cli_row["dof"], cli_row["summed_in"])
        assert f"{py_row['r2_angle']:.3f}" == cli_row["r2_angle"]
        assert f"{py_row['r2_torque']:.3f}" == cli_row["r2_torque"]
    assert (tmp_path / "by-python" / "compare_angles.png").is_file()
    same = dbot.compare(tmp_path / "trials" / "t", tmp_path / "trials" / "t", tmp_path / "self")
    assert all(r["r2_angle"] == pytest.approx(1.0, abs=1e-12) for r in same)


def test_compare_refuses_a_trial_too_short_naming_why(tmp_path: pathlib.Path) -> None:
    record_trial(tmp_path, "short", "virtual", 1)
    with pytest.raises(ValueError, match="at least 2 .*start ramp"):
        dbot.compare(tmp_path / "p", tmp_path / "trials" / "short", tmp_path / "c")

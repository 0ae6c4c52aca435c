"""`Plan.write(dir)` writes the plan directory `dbot plan` writes, by the same library call
(`lab::plan_dir_write`): for the same model and parameters the planner's files are byte for byte
the CLI's (plan.json differs only in where the model came from, which each door names), the
dynamics and strain files are the CLI's, and `read_plan_dir` reads the directory back.

Needs the CLI binary: `cargo build -p dbot` (scripts/test.sh builds it before pytest), or
`DBOT_BIN`."""

from __future__ import annotations

import json
import pathlib

import pytest

import dbot
from dbot_cli import refused, run

SAME_BYTES = ["joints.csv", "feet.csv", "model.urdf", "joint_forces.csv", "strain.csv", "feasibility.md"]


@pytest.fixture(scope="module")
def both(tmp_path_factory: pytest.TempPathFactory) -> tuple[pathlib.Path, pathlib.Path, list[str]]:
    """The tripod of the built-in robot at 40 slices, written by `dbot plan` and by `Plan.write`."""
    d = tmp_path_factory.mktemp("plans")
    run("plan", "--model", "drosophibot2", "--slices", "40", "--name", "tripod", "--out", "cli", cwd=d)
    plan = dbot.plan(dbot.Model.builtin("drosophibot2"), slices=40)
    files = plan.write(d / "py", name="tripod")
    return d / "cli", d / "py", files


def test_python_writes_every_file_the_cli_writes(both) -> None:
    cli, py, files = both
    assert sorted(p.name for p in py.iterdir()) == sorted(files)
    assert sorted(p.name for p in cli.iterdir()) == sorted(files)


@pytest.mark.parametrize("name", SAME_BYTES)
def test_the_files_are_the_clis_byte_for_byte(both, name: str) -> None:
    cli, py, _ = both
    assert (py / name).read_bytes() == (cli / name).read_bytes(), name


def test_plan_json_is_the_clis_but_for_the_model_source(both) -> None:
    cli, py, _ = both
    a = json.loads((cli / "plan.json").read_text())
    b = json.loads((py / "plan.json").read_text())
    assert a.pop("model_source") == "drosophibot2"
    assert b.pop("model_source") == "drosophibot2"
    assert a == b
    # Typed, not free-form: the sections a reader relies on are there with their units.
    assert b["dynamics"]["mu"] == 0.5
    assert b["feasibility"]["feasible"] is True
    assert set(b["feasibility"]["joints"]) == set(dbot.Model.builtin("drosophibot2").servo_joint_names)


def test_the_written_directory_reads_back_with_the_plans_numbers(both) -> None:
    _, py, _ = both
    plan = dbot.plan(dbot.Model.builtin("drosophibot2"), slices=40)
    back = dbot.read_plan_dir(py)
    assert back.table_name == "tripod"
    assert abs(back.angles - plan.angles).max() < 1e-9
    assert abs(back.torques - plan.torques).max() < 1e-6 * max(1.0, abs(plan.torques).max())


def test_without_dynamics_there_are_no_torque_files(tmp_path: pathlib.Path) -> None:
    plan = dbot.plan(dbot.Model.builtin("drosophibot2"), slices=40)
    files = plan.write(tmp_path / "kin", dynamics=False)
    assert "joint_forces.csv" not in files and "strain.csv" not in files
    assert dbot.read_plan_dir(tmp_path / "kin").torques is None
    # A step table needs the torques: Python and `dbot table` refuse the directory in the same
    # words, which name how it came to lack them in either door.
    words = "written without dynamics, by --no-dynamics or Plan.write(dynamics=False)?"
    with pytest.raises(ValueError) as e:
        dbot.read_plan_dir(tmp_path / "kin").step_table()
    assert words in str(e.value) and "torque_nm" in str(e.value)
    stderr = refused("table", "--plan", "kin", "--out", "kin.dbgt", cwd=tmp_path)
    assert words in stderr, stderr
    assert not (tmp_path / "kin.dbgt").exists()


def test_a_name_over_16_bytes_is_refused_with_the_clis_words(tmp_path: pathlib.Path) -> None:
    plan = dbot.plan(dbot.Model.builtin("drosophibot2"), slices=40)
    with pytest.raises(ValueError, match="a gait name has at most 16 bytes"):
        plan.write(tmp_path / "x", name="a-name-that-is-too-long")
    assert not (tmp_path / "x").exists()

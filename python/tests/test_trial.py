"""Trials written by `dbot record`, read through the bindings (`dbot.read_trial`): the arrays are
the trial's telemetry.csv (parsed here with Python's csv module), its metadata is trial.json, and
the plan the table came from is named with the CRC-32 of its model.toml (computed here with zlib).

Needs the CLI binary: `cargo build -p dbot` (scripts/test.sh builds it before pytest), or
`DBOT_BIN`."""

from __future__ import annotations

import csv
import json
import math
import pathlib
import zlib

import numpy as np

import dbot
from dbot_cli import dbot_cli, run



def test_a_trial_reads_back_as_its_files(tmp_path: pathlib.Path) -> None:
    run("plan", "--model", "drosophibot2", "--slices", "40", "--out", "walk", cwd=tmp_path)
    run("table", "--plan", "walk", "--out", "walk/walk.dbgt", cwd=tmp_path)
    run(
        "record", "--out", "trials", "--table", "walk/walk.dbgt", "--play", "0", "--steps", "1",
        "--notes", "from-python", "--port", "virtual", cwd=tmp_path,
    )
    index = (tmp_path / "trials" / "trials.jsonl").read_text().splitlines()
    assert len(index) == 1
    folder = tmp_path / "trials" / json.loads(index[0])["folder"]
    t = dbot.read_trial(folder)

    meta = json.loads((folder / "trial.json").read_text())
    assert t["meta"] == meta
    assert meta["outcome"] == "complete" and meta["notes"] == "from-python"
    assert meta["gait"]["name"] == "walk" and meta["gait"]["slot"] == 0
    model_crc = zlib.crc32((tmp_path / "walk" / "model.toml").read_bytes())
    assert meta["plan"]["model"] == "drosophibot2"
    assert meta["plan"]["model_crc"] == f"{model_crc:08x}"
    plan_json = json.loads((tmp_path / "walk" / "plan.json").read_text())
    assert meta["plan"]["parameters"] == plan_json["parameters"]

    with open(folder / "telemetry.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    joints = t["joint_names"]
    assert len(joints) == 22 and joints == meta["joints"]
    n = len(rows) // 22
    assert t["present_rad"].shape == (n, 22) and t["time_s"].shape == (n,)
    for k in (0, len(rows) // 2, len(rows) - 1):
        r, (i, j) = rows[k], divmod(k, 22)
        assert r["joint"] == joints[j]
        assert int(r["cycle"]) == t["cycle"][i]
        assert math.isclose(float(r["present_rad"]), t["present_rad"][i, j])
        assert int(r["load_raw"]) == t["load_raw"][i, j]
        want = float(r["modelled_torque_nm"]) if r["modelled_torque_nm"] else math.nan
        assert np.isclose(want, t["modelled_torque_nm"][i, j], equal_nan=True)


def test_stop_says_what_it_did() -> None:
    with dbot.Board.open("virtual") as b:
        assert b.stop() == "the robot was not walking"

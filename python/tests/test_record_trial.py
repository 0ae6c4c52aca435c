"""`Board.record_trial` writes the trial folder `dbot record` writes (the same library call,
`lab::trial_record`): read back with `dbot.read_trial`, its metadata is what was asked for and
what the board and the table say (the table's CRC-32 computed here with zlib, the board's
versions from `Board.info`), and the same request through the CLI gives the same metadata except
when it started, its folder and its command line.

Needs the CLI binary: `cargo build -p dbot` (scripts/test.sh builds it before pytest), or
`DBOT_BIN`."""

from __future__ import annotations

import json
import pathlib
import zlib

import dbot
from dbot_cli import run

# The fields that name one recording, not the request.
OWN = ("started", "folder", "command_line")


def plan_and_table(tmp: pathlib.Path) -> pathlib.Path:
    run("plan", "--model", "drosophibot2", "--slices", "40", "--out", "walk", cwd=tmp)
    run("table", "--plan", "walk", "--out", "walk/walk.dbgt", cwd=tmp)
    return tmp / "walk" / "walk.dbgt"


def test_a_trial_written_from_python_is_the_clis_trial(tmp_path: pathlib.Path) -> None:
    table = plan_and_table(tmp_path)
    out = tmp_path / "trials"
    with dbot.Board.open("virtual") as b:
        info = b.info()
        path = b.record_trial(
            str(out), table=str(table), play=0, steps=2, notes="from python", substrate="floor"
        )
    t = dbot.read_trial(path)
    m = t["meta"]
    assert pathlib.Path(path).parent == out and m["folder"] == pathlib.Path(path).name
    assert m["outcome"] == "complete"
    assert m["gait"]["name"] == "walk" and m["gait"]["slot"] == 0
    # The table's CRC-32 covers all of it but its last four bytes, where it is kept.
    assert m["gait"]["crc"] == zlib.crc32(table.read_bytes()[:-4])
    assert m["gait"]["slices"] == 40 and m["gait"]["joints"] == 22
    plan_json = json.loads((tmp_path / "walk" / "plan.json").read_text())
    assert m["plan"]["parameters"] == plan_json["parameters"]
    model_crc = zlib.crc32((tmp_path / "walk" / "model.toml").read_bytes())
    assert m["plan"]["model_crc"] == f"{model_crc:08x}"
    assert m["firmware"]["version"] == info["firmware"]
    assert m["firmware"]["protocol_version"] == info["protocol_version"]
    assert m["firmware"]["table_format_version"] == info["table_format_version"]
    assert m["settings"]["telemetry_every"] == 1 and m["settings"]["cycle_hz"] == 100
    assert m["host_version"] == dbot.__version__
    assert m["command_line"][0] == "python:"
    assert m["command_line"][1].startswith("Board.record_trial(") and "steps=2" in m["command_line"][1]
    assert m["direction"] == "Forward" and m["period_scale"] == 1.0 and m["steps"] == 2
    assert m["substrate"] == "floor" and m["strain"] is False and m["perturbation"] is None
    assert m["notes"] == "from python" and m["port"] == "virtual"
    assert m["started"].endswith("Z") and m["started"][:10] == m["folder"][:10]
    assert m["joints"] == t["joint_names"] and len(m["joints"]) == 22
    # Two steps of 2.5 s at 100 Hz, and the robot standing after them: at least 500 cycles.
    assert m["cycles"] >= 500 and m["cycles"] == len(set(t["cycle"].tolist()))

    run(
        "record", "--out", "trials", "--table", str(table), "--play", "0", "--steps", "2",
        "--notes", "from python", "--substrate", "floor", "--port", "virtual", cwd=tmp_path,
    )
    index = [json.loads(line) for line in (out / "trials.jsonl").read_text().splitlines()]
    assert len(index) == 2 and index[0]["folder"] != index[1]["folder"]
    cli = json.loads((out / index[1]["folder"] / "trial.json").read_text())
    assert cli["command_line"][1:3] == ["record", "--out"]
    assert {k: v for k, v in cli.items() if k not in OWN} == {
        k: v for k, v in m.items() if k not in OWN
    }


def test_refusals_are_the_clis_words_before_anything_moves(tmp_path: pathlib.Path) -> None:
    table = plan_and_table(tmp_path)
    out = tmp_path / "trials"
    with dbot.Board.open("virtual") as b:
        for kwargs, words in [
            (dict(seconds=-1.0), "seconds -1: must be a positive number of seconds"),
            (dict(play=0, steps=2, perturb="XX:1:rise"), "perturb XX:1:rise"),
            (dict(play=0, steps=2, perturb="RM:5:rise"), "perturb RM:5:rise"),
            (dict(), "the virtual robot only walks while the trial records: give --play SLOT"),
            (dict(steps=2), "steps needs a slot to play: give --play SLOT (Python: play=SLOT)"),
            (dict(table=str(tmp_path / "none.dbgt")), f"reading {tmp_path / 'none.dbgt'}"),
        ]:
            try:
                b.record_trial(str(out), **{"table": str(table), **kwargs})
            except ValueError as e:
                assert words in str(e), (kwargs, str(e))
            else:
                raise AssertionError(f"{kwargs} was not refused")
        assert b.status()["state"] == "Idle"
    assert not out.exists() or not any(p.name != "TRIAL INDEX.txt" for p in out.iterdir())


def test_two_trials_in_a_row_never_share_a_folder(tmp_path: pathlib.Path) -> None:
    table = plan_and_table(tmp_path)
    with dbot.Board.open("virtual") as b:
        first = b.record_trial(str(tmp_path / "t"), table=str(table), play=0, steps=1)
        second = b.record_trial(str(tmp_path / "t"), table=str(table), play=0, steps=1)
    assert first != second
    assert dbot.read_trial(first)["meta"]["folder"] != dbot.read_trial(second)["meta"]["folder"]

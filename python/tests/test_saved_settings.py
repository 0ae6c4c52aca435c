"""What `dbot set` keeps beside a `virtual:PATH` store reaches Python: `dbot.Board.open` applies
the saved settings as every `dbot` command does (board::saved_settings, through the library's
opener). The values are the ones given on the command line, read back through `Board.settings()`.

Needs the CLI binary: `cargo build -p dbot --bin dbot` (or `DBOT_BIN`)."""

from __future__ import annotations

import pathlib
import subprocess

import numpy as np
import pytest

import dbot
from dbot_cli import dbot_cli



def test_python_opens_a_store_with_what_dbot_set_saved(tmp_path: pathlib.Path) -> None:
    store = tmp_path / "lab.flash"
    port = f"virtual:{store}"
    # A gait first, so the robot has a joint map (stiffness is per joint of it).
    board = dbot.Board.open(port)
    board.upload_plan(0, dbot.plan(dbot.Model.builtin("drosophibot2"), slices=20))
    fresh = board.settings()
    board.close()
    assert (fresh["baud"], fresh["cycle_hz"]) == (1_000_000, 100)
    out = subprocess.run(
        [
            str(dbot_cli()),
            "set",
            "--port",
            port,
            # The bus rate only: the virtual servos keep their 1 Mbit/s (EEPROM), so a baud change
            # is refused unless they are set first (board::rules::bus); 150 Hz fits 1 Mbit/s.
            "--rate",
            "150",
            "--telemetry-every",
            "7",
            "--stiffness",
            "8.4",
            "--joint",
            "3",
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 0, out.stderr
    assert "settings.json" in out.stdout, out.stdout
    board = dbot.Board.open(port)
    s = board.settings()
    assert (s["baud"], s["cycle_hz"], s["telemetry_every"]) == (1_000_000, 150, 7)
    assert s["stiffness_nm_rad"][3] == pytest.approx(8.4, abs=5e-4)
    # The other joints keep the table's stiffness.
    others = np.delete(s["stiffness_nm_rad"], 3)
    assert np.allclose(others, np.delete(fresh["stiffness_nm_rad"], 3))
    board.close()

"""Strain in closed loop with a strain board beside a board (issue 26 item 6): the emulated board
(the release firmware in the RP2040 emulator, conftest.py) streaming setpoints from Python, a
virtual strain board (`dbot sim-strain`) on a pseudo-terminal beside it attached with
`Board.attach_strain`. Each proprioception record carries the same fields as on the physics
robot: `strain_names` (the board's order), `strain_microstrain` and `strain_age_s`, and
`strain_reading` (per gauge: read through the model's calibration file, or the ESTIMATE gain).

Independent truths: the virtual strain board's counts are 300 + 0.5 x its strain (a sine here,
so they move) and the baseline is its first sample, so every streamed value times 0.5 plus the
first row's counts is a row of the strain.csv the same session wrote; a line ends every 22 ms
or so (254 characters at 115200 bit/s and the board's 2 ms pause), so the latest line is at most
one period old plus the host's scheduling. A strain board that hangs up costs the servo stream
nothing: records keep coming each cycle, `strain_stopped` turns true, the ages grow and
`detach_strain` says why.

Needs the CLI binary for `dbot sim-strain`: `cargo build -p dbot`."""

from __future__ import annotations

import csv
import pathlib
import subprocess
import time

import numpy as np
import pytest

import dbot
from conftest import open_board, record_timeout, servo_rest, standing_board
from dbot_cli import dbot_cli

ROOT = pathlib.Path(__file__).resolve().parents[2]

GAIN = 0.5  # counts per microstrain, `dbot sim-strain`'s default
#: Ages above this on a loaded machine (2 shared cores) would mean the latest line was not used.
MAX_AGE_S = 0.5


def sim_strain(link: pathlib.Path, *args: str) -> subprocess.Popen:
    proc = subprocess.Popen(
        [str(dbot_cli()), "sim-strain", "--link", str(link), *args], stdout=subprocess.DEVNULL
    )
    deadline = time.monotonic() + 60
    while not link.is_symlink():
        assert time.monotonic() < deadline, f"sim-strain never made {link}"
        time.sleep(0.02)
    return proc


def stream(board, target: np.ndarray, cycles: int) -> list[dict]:
    out = []
    for _ in range(cycles):
        board.send_setpoint(target)
        rec = board.next_proprioception(timeout_s=record_timeout(board))
        assert rec is not None, f"no proprioception: {board.status()}"
        out.append(rec)
    return out


def test_each_streamed_record_carries_the_latest_strain_sample_and_its_age(
    tripod_plan, model, emulator_port, tmp_path
) -> None:
    proc = sim_strain(tmp_path / "strain", "--strain", "200", "--sine-hz", "1")
    # A model whose calibration file gives the first gauge 0.25 counts per microstrain: that
    # gauge is read through it, the other 35 through GAIN.
    (tmp_path / "cal.toml").write_text("[gauge.LH_troch_axial]\ncounts_per_microstrain = 0.25\n")
    text = (ROOT / "host" / "planner" / "models" / "drosophibot2.toml").read_text()
    (tmp_path / "m.toml").write_text(f'calibration = "cal.toml"\n{text}')
    calibrated = dbot.Model.load(tmp_path / "m.toml")
    gains = np.array([0.25] + [GAIN] * 35)
    try:
        board = standing_board(tripod_plan, port=emulator_port)
        board.attach_strain(str(tmp_path / "strain"), tmp_path / "s", GAIN, model=calibrated)
        board.enter_streaming(timeout_cycles=50)
        recs = stream(board, servo_rest(tripod_plan, model), 60)
        board.leave_streaming()
        assert board.detach_strain() is None
    finally:
        proc.terminate()
        proc.wait(timeout=15)
    names = recs[0]["strain_names"]
    assert names[:2] == ["LH_troch_axial", "LH_troch_transverse"] and len(names) == 36
    with open(tmp_path / "s" / "strain.csv", newline="") as f:
        rows = [[float(r[n]) for n in names] for r in csv.DictReader(f)]
    first = np.array(rows[0])
    seen = {tuple(np.round((np.array(r) - first) / gains, 9)) for r in rows}
    assert recs[0]["strain_reading"] == ["calibrated"] + ["ESTIMATE"] * 35
    ages = []
    for rec in recs:
        m = rec["strain_microstrain"]
        assert m.shape == (1, 36)
        assert tuple(np.round(m[0], 9)) in seen
        ages.append(float(rec["strain_age_s"][0]))
        assert not rec["strain_stopped"]
    assert 0.0 <= min(ages) and max(ages) < MAX_AGE_S, ages
    # The strain moved while streaming (a 1 Hz sine of 200 microstrain).
    values = np.array([rec["strain_microstrain"][0, 0] for rec in recs])
    assert np.ptp(values) > 50.0, values


def test_a_strain_board_hanging_up_costs_the_servo_stream_nothing(
    tripod_plan, model, emulator_port, tmp_path
) -> None:
    proc = sim_strain(tmp_path / "strain", "--fault", "hangup-at:10")
    try:
        board = standing_board(tripod_plan, port=emulator_port)
        board.attach_strain(str(tmp_path / "strain"), tmp_path / "s", GAIN)
        board.enter_streaming(timeout_cycles=50)
        target = servo_rest(tripod_plan, model)
        # Until the board has hung up (10 lines, about 0.25 s), then on for a while.
        deadline = time.monotonic() + 60
        recs = []
        while not (recs and recs[-1]["strain_stopped"]):
            assert time.monotonic() < deadline, "the strain board never stopped"
            recs += stream(board, target, 1)
        after = stream(board, target, 50)
        assert board.status()["state"] == "Streaming"
        board.leave_streaming()
        error = board.detach_strain()
    finally:
        proc.terminate()
        proc.wait(timeout=15)
    # Every cycle's record came, in order, after the strain stopped too.
    seqs = [int(r["setpoint_seq"][0]) for r in after]
    assert len(after) == 50 and seqs == sorted(seqs)
    assert all(r["strain_stopped"] for r in after)
    # The last sample stays, ever older.
    ages = [float(r["strain_age_s"][0]) for r in after]
    assert ages[-1] > ages[0] and np.all(np.isfinite([r["strain_microstrain"] for r in after]))
    assert error is not None and str(tmp_path / "strain") in error, error


def test_attach_strain_refuses_by_name(emulator_port, tmp_path) -> None:
    board = open_board(emulator_port)
    # The servo board's own port is not a strain board's.
    with pytest.raises(ValueError, match="servo board's port"):
        board.attach_strain(emulator_port, tmp_path / "s", GAIN)
    with pytest.raises(ValueError, match="counts_per_microstrain = 0"):
        board.attach_strain("virtual", tmp_path / "s", 0.0)
    # No gain, and no calibration to give one.
    with pytest.raises(ValueError, match="counts_per_microstrain = None: give the strain board's gain"):
        board.attach_strain("virtual", tmp_path / "s")
    with pytest.raises(ValueError, match="no strain board is attached"):
        board.detach_strain()
    physics = open_board("physics")
    with pytest.raises(ValueError, match="physics robot, whose proprioception already carries"):
        physics.attach_strain("virtual", tmp_path / "p", GAIN)

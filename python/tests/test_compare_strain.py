"""``dbot.compare_strain`` is ``dbot compare --strain``: on the same recording (the physics robot
walking with the in-process strain board reading its simulated gauges, counts = 300 + 0.5 x
microstrain), the same gauges in the same order with the same fitted gain, R^2 and sample count as
the CLI's strain_gains.csv (parsed with Python's csv module, read to its written six decimals).

Not asserted: the fitted gains themselves. The in-process board is paced in host time and the
physics robot is not, so its rows are only as well aligned as the clock fit (docs/strain.md): R^2
of a few hundredths here; the walking comparison aligned by the firmware's slice is
docs/validation.md's strain_walking block.

Needs the CLI binary: `cargo build -p dbot` (scripts/test.sh builds it before pytest)."""

from __future__ import annotations

import pathlib

import dbot
from dbot_cli import csv_rows, record_trial, run


def test_compare_strain_from_python_gives_the_cli_rows(tmp_path: pathlib.Path) -> None:
    record_trial(tmp_path, "t", "physics", 3, "--strain", "virtual")
    run("compare", "--strain", "trials/t", "p", "--out", "by-cli", cwd=tmp_path)
    cli_rows = csv_rows(tmp_path / "by-cli" / "strain_gains.csv")
    rows = dbot.compare_strain(tmp_path / "trials" / "t", tmp_path / "p")
    assert len(rows) == len(cli_rows) == 36
    cell = lambda v: "" if v is None else f"{v + 0.0:.6f}"  # noqa: E731 (the CLI's format)
    for py_row, cli_row in zip(rows, cli_rows):
        assert py_row["gauge"] == cli_row["gauge"]
        assert cell(py_row["gain"]) == cli_row["counts_per_microstrain"]
        assert cell(py_row["r2"]) == cli_row["r2"]
        assert str(py_row["samples"]) == cli_row["samples"]
        assert py_row["samples"] > 0
    # Every gauge of the board, in its order (legs LH, RH, LM, RM, LF, RF), was compared.
    legs = ["LH", "RH", "LM", "RM", "LF", "RF"]
    assert [r["gauge"][:2] for r in rows] == [leg for leg in legs for _ in range(6)]

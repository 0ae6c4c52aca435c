"""The `dbot` CLI binary for the tests that compare Python with what the CLI writes or refuses:
`target/debug/dbot` (from `cargo build -p dbot`; scripts/test.sh builds it before pytest), or the
path in `DBOT_BIN`. A missing binary fails the test rather than skipping it, so that a test cannot
pass without running."""

from __future__ import annotations

import csv
import os
import pathlib
import subprocess

ROOT = pathlib.Path(__file__).resolve().parents[2]


def dbot_cli() -> pathlib.Path:
    if os.environ.get("DBOT_BIN"):
        return pathlib.Path(os.environ["DBOT_BIN"])
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    exe = target / "debug" / "dbot"
    assert exe.exists(), f"{exe} is missing: build it with `cargo build -p dbot` (or set DBOT_BIN)"
    return exe


def run(*args: str, cwd: pathlib.Path) -> str:
    """Runs `dbot ARGS` in `cwd`; it must succeed. Its standard output."""
    out = subprocess.run(
        [str(dbot_cli()), *args], cwd=cwd, capture_output=True, text=True, timeout=600
    )
    assert out.returncode == 0, out.stderr
    return out.stdout


def refused(*args: str, cwd: pathlib.Path) -> str:
    """Runs `dbot ARGS` in `cwd`; it must fail. Its standard error."""
    out = subprocess.run(
        [str(dbot_cli()), *args], cwd=cwd, capture_output=True, text=True, timeout=600
    )
    assert out.returncode != 0, out.stdout
    return out.stderr


def record_trial(cwd: pathlib.Path, trial: str, port: str, steps: int, *extra: str) -> None:
    """Plans 40 slices into `p`, tables them as `p/g.dbgt` and records `steps` steps of that table
    played in slot 0 on `port` as `trials/TRIAL` (`extra`: more `dbot record` arguments)."""
    run("plan", "--slices", "40", "--out", "p", cwd=cwd)
    run("table", "--plan", "p", "--out", "p/g.dbgt", cwd=cwd)
    run("record", "--out", "trials", "--trial", trial, "--table", "p/g.dbgt", "--play", "0",
        "--steps", str(steps), "--port", port, *extra, cwd=cwd)


def csv_rows(path: pathlib.Path) -> list[dict[str, str]]:
    """The rows of a CSV file the CLI wrote, by header (Python's csv module)."""
    with open(path, newline="") as f:
        return list(csv.DictReader(f))

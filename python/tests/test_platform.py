"""The perturbation platform from Python as from the CLI (issue 29 item 3): ``Board.set_platform``
and ``dbot record --perturb`` parse ``LEG:STEP:MOVE`` with the same library call
(``board::platform::Perturb``), so a leg that is not a leg and a step beyond the run are refused in
the same words, before anything moves; a platform servo that does not answer (the virtual robot
has none) is named by its ID, as ``dbot record`` names it.

Needs the CLI binary: ``cargo build -p dbot`` (or ``DBOT_BIN``)."""

from __future__ import annotations

import os
import pathlib
import subprocess

import pytest

import dbot
from dbot_cli import dbot_cli


def refusal(*args: str, cwd: pathlib.Path) -> str:
    env = {k: v for k, v in os.environ.items() if k != "DBOT_CONFIG"}
    env["XDG_CONFIG_HOME"] = str(cwd)
    out = subprocess.run(
        [str(dbot_cli()), *args], cwd=cwd, capture_output=True, text=True, timeout=600, env=env
    )
    assert out.returncode != 0, out.stdout
    return out.stderr


@pytest.mark.parametrize(
    ("spec", "words"),
    [
        ("LX:1:rise", "perturbation leg `LX` is not a leg (legs: LF, LM, LH, RF, RM, RH)"),
        (
            "RM:2:rise",
            "perturbation step 2 is beyond the run's 2 steps (steps count from 0, so the last is 1)",
        ),
    ],
)
def test_python_and_the_cli_refuse_a_perturbation_in_the_same_words(
    tmp_path: pathlib.Path, spec: str, words: str
) -> None:
    by_cli = refusal(
        "record", "--out", str(tmp_path / "trials"), "--play", "0", "--steps", "2",
        "--port", "virtual", "--perturb", spec, cwd=tmp_path,
    )
    assert words in by_cli, by_cli
    with dbot.Board.open("virtual") as board, pytest.raises(ValueError) as e:
        board.set_platform(spec, steps=2)
    assert words in str(e.value), e.value
    # Nothing was set up on the board.
    assert not (tmp_path / "trials").exists() or not any((tmp_path / "trials").iterdir())


def test_a_platform_servo_that_does_not_answer_is_named() -> None:
    with dbot.Board.open("virtual") as board:
        with pytest.raises(Exception) as e:
            board.set_platform("LF:0:rise", platform_id=23)
        assert (
            "virtual: perturbation platform: platform servo ID 23 does not answer (ping, profile "
            "velocity or position read failed): check its cable and ID"
        ) in str(e.value)
        board.clear_platform()

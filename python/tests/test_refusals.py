"""The rules that protect the robot refuse from Python as from the CLI, in the same words: the library
call that builds or uploads a step table (``board::rules``) is the one both doors use.

The same infeasible plan (the paper's 0.5 s swing, ``--preset table1``, too fast for the front FTi
servos) is refused by ``PlanDir.step_table()``, ``Plan.step_table()`` and ``Board.upload_plan()``
with the text ``dbot table`` prints; ``allow_infeasible=True`` builds the bytes
``dbot table --allow-infeasible`` writes, with the CLI's warning. ``Board.play(period_scale=)``
refuses a scale at which a servo could not follow the table as ``dbot run --period`` does (and
``Board.record_trial(period=)`` as ``dbot record --period``), with the speed computed here by hand (planned peak speed / scale against the MX-28's 55 rev/min no-load
speed from its e-manual). ``Board.steer(speed=)`` refuses a speed at which a servo could not follow
the family's tables as ``dbot steer --speed`` does, with the same words. ``Board.upload(slot,
bytes)`` checks the bytes as ``dbot upload --table`` checks a file, and ``Board.queue_gait``
meets ``play``'s period rule.

Needs the CLI binary: ``cargo build -p dbot`` (or ``DBOT_BIN``)."""

from __future__ import annotations

import math
import os
import pathlib
import subprocess
import warnings

import pytest

import dbot
from dbot_cli import dbot_cli

#: MX-28(2.0) no-load speed at 12 V: 55 rev/min (e-manual), rad/s.
MX28_NO_LOAD = 55.0 * 2.0 * math.pi / 60.0


def cli(*args: str, cwd: pathlib.Path) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if k != "DBOT_CONFIG"}
    env["XDG_CONFIG_HOME"] = str(cwd)
    env["RUST_BACKTRACE"] = "0"
    return subprocess.run(
        [str(dbot_cli()), *args], cwd=cwd, capture_output=True, text=True, timeout=600, env=env
    )


def ok(*args: str, cwd: pathlib.Path) -> str:
    out = cli(*args, cwd=cwd)
    assert out.returncode == 0, out.stderr
    return out.stdout


def refusal(*args: str, cwd: pathlib.Path) -> str:
    """The text after ``Error: `` of a command that must fail."""
    out = cli(*args, cwd=cwd)
    assert out.returncode != 0, out.stdout
    assert out.stderr.startswith("Error: "), out.stderr
    return out.stderr.removeprefix("Error: ").rstrip()


def peak_speed(q: list[float], dt: float) -> float:
    """Peak |dq/dt| of a periodic cycle by central differences (the paper's equation 1)."""
    n = len(q)
    return max(abs(q[(s + 1) % n] - q[(s - 1) % n]) / (2.0 * dt) for s in range(n))


def named_speed(text: str, joint: str) -> float:
    line = next(ln for ln in text.splitlines() if ln.strip().startswith(f"{joint} at slice"))
    return float(line.split(": ")[1].split(" ")[0])


def read_relative(plans: pathlib.Path, name: str) -> dbot.PlanDir:
    """The plan directory `name` read from inside `plans`, by the relative path the CLI was given,
    so that it is named in messages as the CLI names it."""
    cwd = os.getcwd()
    os.chdir(plans)
    try:
        return dbot.read_plan_dir(name)
    finally:
        os.chdir(cwd)


@pytest.fixture(scope="module")
def plans(tmp_path_factory: pytest.TempPathFactory) -> pathlib.Path:
    """``fast``: table 1's 0.5 s swing (1.25 s per step); ``safe``: the default servo-safe preset
    (2.5 s per step); 50 slices each, with dynamics."""
    d = tmp_path_factory.mktemp("refusals")
    ok("plan", "--preset", "table1", "--slices", "50", "--out", "fast", cwd=d)
    ok("plan", "--slices", "50", "--out", "safe", cwd=d)
    return d


def test_plan_dir_step_table_and_upload_plan_refuse_with_the_cli_words(plans: pathlib.Path) -> None:
    by_cli = refusal("table", "--plan", "fast", "--out", "t.dbgt", cwd=plans)
    assert by_cli.startswith("plan fast: the servos cannot follow this plan:\n"), by_cli
    # The PlanDir read from the same relative path names it as the CLI does.
    fast = read_relative(plans, "fast")
    with pytest.raises(ValueError) as e:
        fast.step_table()
    assert str(e.value) == by_cli
    with dbot.Board.open("virtual") as board:
        with pytest.raises(ValueError) as e:
            board.upload_plan(3, fast)
        assert str(e.value) == by_cli
        # Nothing reached the board.
        assert next(g for g in board.gaits() if g["slot"] == 3)["gait"] is None
    # The speed named is the peak of the plan's own angles (joints.csv) over 55 rev/min.
    j = fast.joint_names.index("LF_FTi")
    peak = peak_speed([float(a) for a in fast.angles[:, j]], fast.period_s / fast.slices)
    assert peak > MX28_NO_LOAD
    assert abs(named_speed(by_cli, "LF_FTi") - peak) < 0.006
    assert f"no-load speed {MX28_NO_LOAD:.2f} rad/s" in by_cli


def test_a_plan_in_memory_is_refused_with_the_same_violations(plans: pathlib.Path) -> None:
    by_cli = refusal("table", "--plan", "fast", "--out", "t.dbgt", cwd=plans)
    p = dbot.plan(dbot.Model.builtin("drosophibot2"), preset="table1", slices=50)
    with pytest.raises(ValueError) as e:
        p.step_table(torques=True)
    words = str(e.value)
    assert words.startswith("plan of drosophibot2: the servos cannot follow this plan:\n"), words
    # After the line naming the plan: the same joints, slices and margins, the same advice.
    assert words.split("\n", 1)[1] == by_cli.split("\n", 1)[1]
    with dbot.Board.open("virtual") as board, pytest.raises(ValueError) as e:
        board.upload_plan(2, p, torques=True)
    assert str(e.value) == words


def test_allow_infeasible_builds_the_cli_bytes_with_the_cli_warning(plans: pathlib.Path) -> None:
    out = cli("table", "--plan", "fast", "--out", "t.dbgt", "--allow-infeasible", cwd=plans)
    assert out.returncode == 0, out.stderr
    cli_bytes = (plans / "t.dbgt").read_bytes()
    fast = read_relative(plans, "fast")
    with pytest.warns(UserWarning) as w:
        table = fast.step_table(allow_infeasible=True)
    assert table == cli_bytes
    assert out.stderr.rstrip() == "warning: " + str(w[0].message)
    with dbot.Board.open("virtual") as board:
        with pytest.warns(UserWarning):
            sent = board.upload_plan(3, fast, allow_infeasible=True)
        assert sent == len(cli_bytes)


def test_a_period_scale_the_servos_cannot_follow_is_refused_as_run_period(
    plans: pathlib.Path,
) -> None:
    ok("upload", "--plan", "safe", "--slot", "1", "--port", "virtual:robot.flash", "--create",
       cwd=plans)
    # 1.0 s per step of a 2.5 s plan: scale 0.4, every speed 2.5 times the planned one.
    by_cli = refusal("run", "--slot", "1", "--steps", "1", "--period", "1.0",
                     "--port", "virtual:robot.flash", cwd=plans)
    safe = read_relative(plans, "safe")
    j = safe.joint_names.index("LF_FTi")
    planned = peak_speed([float(a) for a in safe.angles[:, j]], safe.period_s / safe.slices)
    assert planned < MX28_NO_LOAD < planned / 0.4
    with dbot.Board.open("virtual") as board:
        board.upload_plan(1, safe)
        with pytest.raises(ValueError) as e:
            board.play(1, steps=1, period_scale=0.4)
        assert str(e.value) == by_cli
        # Table angles are kept to 1e-4 rad: at most 1e-4 / (2 x 0.02 s) = 0.0025 rad/s off.
        assert abs(named_speed(by_cli, "LF_FTi") - planned / 0.4) < 0.008
        assert f"no-load speed {MX28_NO_LOAD:.2f} rad/s" in by_cli
        # Nothing was played. (Boot: the upload selected slot 1 of an erased store, new servo IDs,
        # so the board is finding them; no simulated time passes between these calls.)
        assert board.status()["state"] in ("Boot", "Idle", "Standing")
        # Slower than planned needs no check.
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            board.play(1, steps=1, period_scale=1.2)
        board.stop()


def test_table_bytes_are_refused_by_upload_as_by_dbot_upload_table(plans: pathlib.Path) -> None:
    # A table built with the override meets the rule again when uploaded (it used to upload
    # unchecked from both doors): the same joints, margins and advice after the line naming it.
    ok("table", "--plan", "fast", "--out", "tf.dbgt", "--allow-infeasible", cwd=plans)
    by_cli = refusal("upload", "--table", "tf.dbgt", "--slot", "2",
                     "--port", "virtual:file.flash", "--create", cwd=plans)
    assert by_cli.startswith("step table tf.dbgt: the servos cannot follow this plan:\n"), by_cli
    table = (plans / "tf.dbgt").read_bytes()
    with dbot.Board.open("virtual") as board:
        with pytest.raises(ValueError) as e:
            board.upload(2, table)
        words = str(e.value)
        assert words.startswith("step table: the servos cannot follow this plan:\n"), words
        assert words.split("\n", 1)[1] == by_cli.split("\n", 1)[1]
        assert next(g for g in board.gaits() if g["slot"] == 2)["gait"] is None
        with pytest.warns(UserWarning):
            assert board.upload(2, table, allow_infeasible=True) == len(table)


def test_a_queued_gait_faster_than_the_servos_follow_is_refused_as_play(
    plans: pathlib.Path,
) -> None:
    safe = read_relative(plans, "safe")
    with dbot.Board.open("virtual") as board:
        board.upload_plan(1, safe)
        with pytest.raises(ValueError) as by_play:
            board.play(1, steps=1, period_scale=0.4)
        board.play(1, steps=1)
        # `queue_gait(period_scale=)` used to reach the board unchecked.
        with pytest.raises(ValueError) as e:
            board.queue_gait(1, steps=1, period_scale=0.4)
        assert str(e.value) == str(by_play.value)
        with pytest.warns(UserWarning):
            board.queue_gait(1, steps=1, period_scale=0.4, allow_infeasible=True)
        board.stop()


def test_a_trial_played_faster_than_the_servos_follow_is_refused_as_run_period(
    plans: pathlib.Path, tmp_path: pathlib.Path
) -> None:
    ok("upload", "--plan", "safe", "--slot", "1", "--port", "virtual:trial.flash", "--create",
       cwd=plans)
    by_run = refusal("run", "--slot", "1", "--steps", "1", "--period", "1.0",
                     "--port", "virtual:trial.flash", cwd=plans)
    by_record = refusal("record", "--out", "trials", "--play", "1", "--steps", "1",
                        "--period", "1.0", "--port", "virtual:trial.flash", cwd=plans)
    assert by_record == by_run
    out = tmp_path / "trials"
    with dbot.Board.open("virtual") as board:
        board.upload_plan(1, read_relative(plans, "safe"))
        with pytest.raises(ValueError) as e:
            board.record_trial(out, play=1, steps=1, period=1.0)
        assert str(e.value) == by_run
        assert [p.name for p in out.glob("*") if p.is_dir()] == []
        with pytest.warns(UserWarning, match="the servos cannot follow this plan"):
            folder = board.record_trial(out, play=1, steps=1, period=1.0, allow_infeasible=True)
        assert (pathlib.Path(folder) / "trial.json").is_file()


def test_a_table_the_cli_uploaded_is_checked_from_the_image(plans: pathlib.Path) -> None:
    ok("upload", "--plan", "safe", "--slot", "2", "--port", "virtual:image.flash", "--create",
       cwd=plans)
    by_cli = refusal("run", "--slot", "2", "--steps", "1", "--period", "1.0",
                     "--port", "virtual:image.flash", cwd=plans)
    # This `Board` did not upload slot 2: the host reads its table from the robot's image.
    with dbot.Board.open(f"virtual:{plans / 'image.flash'}") as board:
        with pytest.raises(ValueError) as e:
            board.play(2, steps=1, period_scale=0.4)
        assert str(e.value) == by_cli


def test_a_steering_speed_the_servos_cannot_follow_is_refused_as_steer_speed(
    plans: pathlib.Path,
) -> None:
    port = ("--port", "virtual:steer.flash")
    ok("upload", "--plan", "safe", "--slot", "1", *port, "--create", cwd=plans)
    steer = ("steer", "--family", "1,1,1", "--range", "0.06", "--heading", "0", "--steps", "1")
    # Speed 2.5: the 2.5 s plan at 1.0 s per step, every speed 2.5 times the planned one.
    by_cli = refusal(*steer, "--speed", "2.5", *port, cwd=plans)
    assert by_cli.startswith(
        'steering at speed 2.5: slot 1 ("safe"): at 1.000 s per step (0.400 times the planned '
        "2.500 s) the servos cannot follow it:\n"
    ), by_cli
    out = cli(*steer, "--speed", "2.5", "--allow-infeasible", *port, cwd=plans)
    assert out.returncode == 0, out.stderr
    safe = read_relative(plans, "safe")
    j = safe.joint_names.index("LF_FTi")
    planned = peak_speed([float(a) for a in safe.angles[:, j]], safe.period_s / safe.slices)
    assert planned < MX28_NO_LOAD < planned * 2.5
    assert abs(named_speed(by_cli, "LF_FTi") - planned * 2.5) < 0.008
    with dbot.Board.open("virtual") as board:
        board.upload_plan(1, safe)
        board.set_steer_family(1, 1, 1, 0.06)
        with pytest.raises(ValueError) as e:
            board.steer(0.0, 2.5)
        assert str(e.value) == by_cli
        assert board.status()["state"] in ("Boot", "Idle", "Standing")
        # As planned nothing is checked; the override steers with the CLI's warning.
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            board.steer(0.0, 1.0)
        board.stop()
        with pytest.warns(UserWarning) as w:
            board.steer(0.0, 2.5, allow_infeasible=True)
        board.stop()
    assert out.stderr.startswith("warning: " + str(w[0].message)), out.stderr


def test_steering_fast_over_a_family_set_elsewhere_is_refused() -> None:
    """A `Board` that did not set the family does not know which tables to check."""
    with dbot.Board.open("virtual") as board:
        with pytest.raises(ValueError, match="this host did not set the family"):
            board.steer(0.0, 2.0)


def test_a_stiffness_the_p_gain_register_cannot_hold_is_refused_as_by_set(
    plans: pathlib.Path,
) -> None:
    ok("upload", "--plan", "safe", "--slot", "0", "--port", "virtual:stiff.flash", "--create",
       cwd=plans)
    by_cli = refusal("set", "--stiffness", "240", "--port", "virtual:stiff.flash", cwd=plans)
    # The CLI names its flag, Python the joint; the rule's words after that are the same.
    words = by_cli.removeprefix("--stiffness 240: ")
    assert words.startswith("stiffness 240 N m/rad is more than the MX-28(2.0)'s"), by_cli
    with dbot.Board.open("virtual") as board:
        safe = read_relative(plans, "safe")
        board.upload_plan(0, safe)
        with pytest.raises(ValueError) as e:
            board.set_stiffness(0, 240.0)
        assert str(e.value) == "joint 0: " + words
        # 0 is the torque bias off, as `dbot set --stiffness 0`.
        board.set_stiffness(0, 0.0)
        assert board.settings()["stiffness_nm_rad"][0] == 0.0


def test_set_torque_switches_every_servo_and_takes_no_joint() -> None:
    # The board switches all servos together and refused one joint alone (`Unsupported`): the
    # keyword that promised it is gone (issue 43).
    with dbot.Board.open("virtual") as b:
        with pytest.raises(TypeError):
            b.set_torque(True, joint=0)  # type: ignore[call-arg]
        b.set_torque(False)
        assert b.status()["torque_enabled"] == 0

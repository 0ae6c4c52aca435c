"""dbot.identify, dbot.replay and dbot.stand_in_trials: the stand-in robot (every servo-dynamics
parameter away from the default) identified from Python through the call ``dbot identify`` makes,
and its held-out walk replayed closer on the fitted model than on the one it started from."""

from __future__ import annotations

import math
import pathlib
import tomllib

import pytest

import dbot

TICK = 2 * math.pi / 4096


def test_the_stand_in_is_identified_from_python(tmp_path) -> None:
    t = dbot.stand_in_trials(tmp_path / "trials", joints=["LF_CTr", "LM_FTi"], short=True)
    assert [pathlib.Path(p).name for p in t["suspended"]] == ["sus-CTr", "sus-FTi"]
    out = tmp_path / "fitted.toml"
    fitted = dbot.identify(t["suspended"], t["start"], out=out)
    assert isinstance(fitted, dbot.Model)
    assert (tmp_path / "fitted-report" / "report.md").is_file()
    # The model file names a joint by its child body: LM_FTi moves LM_Tibia.
    joint = next(j for j in tomllib.loads(out.read_text())["joint"] if j["child"] == "LM_Tibia")
    got = joint["servo_dynamics"]
    # The stand-in's MX-28 (lab::identify::stand_in): P divisor 160, stall 0.9 x 2.5 N m,
    # friction 0.03 N m, deadband 2 ticks, backlash 3 ticks, load gain 0.8, offset 0.05 N m in
    # steps of 2 counts.
    for field, truth in [
        ("p_gain_divisor", 160.0),
        ("stall_torque_nm", 2.25),
        ("friction_nm", 0.03),
        ("load_gain", 0.8),
        ("load_offset_nm", 0.05),
    ]:
        assert got[field] == pytest.approx(truth, rel=0.10), field
    assert abs(got["deadband_rad"] - 2 * TICK) <= TICK
    assert abs(got["backlash_rad"] - 3 * TICK) <= TICK
    assert got["load_resolution_counts"] == 2

    before = dbot.replay(t["walk"], t["start"])
    after = dbot.replay(t["walk"], fitted)
    assert after["position_rms_rad"] * 3 <= before["position_rms_rad"]
    assert {j["load_reading"] for j in before["joints"]} == {"ESTIMATE"}
    assert {j["load_reading"] for j in after["joints"]} == {"calibrated"}


def test_a_walk_alone_fits_only_the_ground_friction(tmp_path) -> None:
    # The stand-in's walk is on the default ground (friction 1.5, sand paper): its feet do not
    # slip, so the friction is named as not identified and the fitted model keeps the default;
    # without a suspended trial the servo dynamics are kept as given (lab::identify).
    t = dbot.stand_in_trials(tmp_path / "trials", joints=["LM_FTi"], short=True)
    out = tmp_path / "fitted.toml"
    dbot.identify([t["walk"]], t["start"], out=out)
    report = (tmp_path / "fitted-report" / "report.md").read_text()
    assert "- `foot_friction`: the feet hardly slip" in report
    assert "- `servo dynamics`: no suspended trial given" in report
    assert "foot_friction" not in tomllib.loads(out.read_text())

"""dbot.excitation: the excitation trials that identify the robot, as ``dbot excite`` writes them."""

from __future__ import annotations

import math

import numpy as np
import pytest

import dbot


def test_suspended_trials_stay_within_limits_and_speed_and_carry_checked_tables() -> None:
    m = dbot.Model.builtin("drosophibot2")
    trials = dbot.excitation("suspended", m)
    assert [t["name"] for t in trials] == ["sus-ThC1", "sus-ThC3", "sus-CTr", "sus-TrF1", "sus-FTi"]
    names = list(m.servo_joint_names)
    limits = dict(zip(m.joint_names, m.limits))
    # e-manual no-load speeds at 12 V: MX-28 55 rev/min, MX-64 63 rev/min; the CTr are MX-64.
    for t in trials:
        assert t["joint_names"] == names
        q = t["goals_rad"]
        assert q.shape == (round(t["period_s"] / t["dt_s"]), len(names))
        for k, name in enumerate(names):
            lo, hi = limits[name]
            assert np.all(q[:, k] >= lo) and np.all(q[:, k] <= hi), name
            rpm = 63.0 if name.endswith("CTr") else 55.0
            speed = np.abs(np.diff(q[:, k])) / t["dt_s"]
            # Half the no-load speed; the dynamixel crate holds it in f32 (1e-6 relative).
            assert speed.max() <= 0.5 * rpm * 2 * math.pi / 60 * (1 + 1e-6), name
        # The table bytes: the DBGT magic, and as many slices as goals.
        assert t["table"][:4] == b"DBGT"
        chirps = [s for s in t["segments"] if s["motion"] == "chirp"]
        assert chirps and all((s["f0_hz"], s["f1_hz"]) == (0.1, 2.0) for s in chirps)


def test_standing_is_one_table_and_an_unknown_kind_is_refused() -> None:
    (t,) = dbot.excitation("standing")
    assert t["name"] == "stand"
    assert [s["what"] for s in t["segments"]] == ["heave", "surge", "sway", "roll", "pitch", "yaw"]
    with pytest.raises(ValueError, match="suspended or standing"):
        dbot.excitation("hanging")

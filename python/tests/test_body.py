"""The physics robot's body from Python (``Board.body()``), checked against independent truth:

* standing still, the ground carries the whole robot: the vertical contact forces on the six feet
  sum to its weight, m g, with m summed by hand from the model file's bodies
  (host/planner/models/drosophibot2.toml) and g = 9.81 m/s^2 (planner::terrain::G, the MJCF's
  gravity). Standing still the thorax's acceleration is zero, so Newton's second law leaves no
  other vertical force. Tolerance: 1 % (the body still sways a little after the gravity ramp; the
  test waits 1.5 s beyond it, and averages 50 cycles);
* walking, the thorax stays near the height the gait was planned for: the body is set down in the
  planner's stance (175 mm for the default plan), within 20 mm (measured: 162 to 176 mm while
  walking the default servo-safe tripod; it sags most at the end of a tripod's stance);
* only the physics robot has a body: the virtual robot says so, naming the port.
"""

from __future__ import annotations

import math
import pathlib
import tomllib

import numpy as np
import pytest

import dbot

ROOT = pathlib.Path(__file__).resolve().parents[2]
MODEL_FILE = ROOT / "host" / "planner" / "models" / "drosophibot2.toml"
#: Gravity of the physics robot's flat scene, m/s^2 (planner::terrain::G).
G = 9.81
#: The thorax height of the planner's stance for the default plan, m.
PLANNED_HEIGHT_M = 0.175


def hand_mass_kg() -> float:
    """Every body's mass in the model file, summed here (not by the library)."""
    doc = tomllib.loads(MODEL_FILE.read_text())
    return math.fsum(b["mass_kg"] for b in doc["body"])


def test_model_masses_agree_with_the_file() -> None:
    # The library's model is the file's: the same total mass.
    assert dbot.Model.builtin("drosophibot2").mass_kg == pytest.approx(hand_mass_kg(), rel=1e-12)


def test_standing_the_feet_carry_the_weight() -> None:
    board = dbot.Board.open("physics")
    assert board.kind == "physics"
    model = dbot.Model.builtin("drosophibot2")
    board.upload_plan(0, dbot.plan(model, slices=20))
    # Torque on holds the stance the body was set down in; gravity ramps in over 1 s.
    board.set_torque(True)
    board.wait(2.5)
    assert board.status()["state"] == "Standing"
    weight = hand_mass_kg() * G
    fz = []
    for _ in range(50):
        board.wait(0.01)
        b = board.body()
        assert b["feet"] == ["LF", "LM", "LH", "RF", "RM", "RH"]
        assert b["foot_force_n"].shape == (6, 3)
        fz.append(b["foot_force_n"][:, 2].sum())
    total = float(np.mean(fz))
    assert total == pytest.approx(weight, rel=0.01), (total, weight)
    b = board.body()
    assert b["foot_contact"].all(), b["foot_contact"]
    # Standing: nothing slides and the thorax is still.
    assert np.all(b["foot_slip_m_s"] < 5e-3), b["foot_slip_m_s"]
    assert np.linalg.norm(b["thorax_velocity_m_s"]) < 5e-3
    # The orientation is a unit quaternion, and roll/pitch/yaw is the same rotation.
    q = b["thorax_orientation"]
    assert np.linalg.norm(q) == pytest.approx(1.0, abs=1e-9)
    roll, pitch, yaw = b["thorax_rpy_rad"]
    w = math.cos(roll / 2) * math.cos(pitch / 2) * math.cos(yaw / 2) + math.sin(
        roll / 2
    ) * math.sin(pitch / 2) * math.sin(yaw / 2)
    assert abs(w) == pytest.approx(abs(q[0]), abs=1e-9)
    # Simulated time is the board's clock (the body rests at the next cycle's start).
    assert abs(b["time_s"] - board.now()) <= 0.011
    board.close()


def test_walking_the_thorax_stays_near_the_planned_height() -> None:
    board = dbot.Board.open("physics")
    model = dbot.Model.builtin("drosophibot2")
    gait = dbot.plan(model, slices=50)
    board.upload_plan(0, gait)
    board.play(0, steps=2)
    heights, xs, stance_contact = [], [], []
    t0 = board.now()
    t_end = t0 + 0.6 + 2 * gait.period_s
    while board.now() < t_end:
        board.wait(0.05)
        b = board.body()
        heights.append(b["thorax_position_m"][2])
        xs.append(b["thorax_position_m"][0])
        # Gravity ramps in over the first second after torque-on (the robot is set down).
        if b["time_s"] > t0 + 1.0:
            stance_contact.append(int(b["foot_contact"].sum()))
    assert board.status()["fault"] is None
    heights = np.array(heights)
    assert np.all(np.abs(heights - PLANNED_HEIGHT_M) < 0.020), (heights.min(), heights.max())
    # It walked forward (x forward; measured 0.32 m in the two steps), and a tripod always has at
    # least three feet down.
    assert xs[-1] - xs[0] > 0.2, (xs[0], xs[-1])
    assert min(stance_contact) >= 3, stance_contact
    board.close()


def test_only_the_physics_robot_has_a_body() -> None:
    board = dbot.Board.open("virtual")
    assert board.kind == "virtual"
    with pytest.raises(dbot.BoardError, match="virtual.*no simulated body.*physics"):
        board.body()
    board.close()

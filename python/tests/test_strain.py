"""Predicted gauge strain through the bindings: ``Plan.strain`` and ``Plan.gauge_names``.

Independent truths: the gauge order is the lab's strain board's (``../shared/reference/
lab-practice.md``: legs LH, RH, LM, RM, LF, RF; per leg trochanter axial, transverse, 45 deg,
femur +45, -45 deg, axial), and at one site the transverse gauge reads minus Poisson's ratio
(0.39 in the model file) times the axial gauge (Hooke's law in plane stress, whatever the load).
"""

from __future__ import annotations

import pathlib

import numpy as np

import dbot

BOARD_LEGS = ["LH", "RH", "LM", "RM", "LF", "RF"]
MODEL_FILE = pathlib.Path(__file__).resolve().parents[2] / "host" / "planner" / "models" / "drosophibot2.toml"
PER_LEG = ["troch_axial", "troch_transverse", "troch_45", "femur_plus45", "femur_minus45", "femur_axial"]


def test_plan_strain_is_slice_by_gauge_in_board_order() -> None:
    p = dbot.plan(dbot.Model.builtin("drosophibot2"), slices=20)
    assert p.gauge_names == [f"{leg}_{g}" for leg in BOARD_LEGS for g in PER_LEG]
    s = p.strain
    assert s.shape == (20, 36)
    assert np.all(np.isfinite(s))
    # Stance legs carry the robot: hundreds of microstrain somewhere, not zero.
    assert np.max(np.abs(s)) > 50.0
    names = p.gauge_names
    for leg in BOARD_LEGS:
        axial = s[:, names.index(f"{leg}_troch_axial")]
        transverse = s[:, names.index(f"{leg}_troch_transverse")]
        np.testing.assert_allclose(transverse, -0.39 * axial, rtol=1e-12, atol=1e-9)


def test_a_model_without_gauges_has_an_empty_strain_array(tmp_path) -> None:
    text = MODEL_FILE.read_text()
    path = tmp_path / "no-gauges.toml"
    path.write_text(text[: text.index("[[gauge]]")])
    p = dbot.plan(dbot.Model.load(path), slices=20)
    assert p.gauge_names == []
    assert p.strain.shape == (20, 0)


def test_board_record_with_the_virtual_strain_board_beside_it(tmp_path) -> None:
    # The in-process strain board at zero strain streams what calibration trimmed every gauge
    # to: 300 counts (lab-practice.md: 300 +- 75), 36 gauges in the board's order.
    from conftest import open_board

    plan = dbot.plan(dbot.Model.builtin("drosophibot2"), slices=20)

    def walk(**strain) -> dict:
        board = open_board("virtual")
        board.upload_plan(0, plan)
        board.set_telemetry(1)
        board.play(0, steps=1)
        return board.record(plan.period_s + 1.0, **strain)

    rec = walk(strain="virtual", strain_dir=tmp_path)
    assert rec["strain_error"] is None
    assert rec["strain_names"] == [f"{leg}_{g}" for leg in BOARD_LEGS for g in PER_LEG]
    counts = rec["strain_counts"]
    assert counts.shape[1] == 36 and counts.shape[0] >= 1
    assert np.all(counts == 300.0)
    assert np.all(np.isfinite(rec["strain_time_s"]))
    assert (tmp_path / "strain.csv").is_file() and (tmp_path / "strain_clock.csv").is_file()
    # The telemetry is the same walk's as without strain (the virtual robot's clock is simulated).
    np.testing.assert_array_equal(rec["cycle"], walk()["cycle"])
    assert "strain_counts" not in walk()


def test_strain_without_a_folder_is_refused_by_name() -> None:
    from conftest import open_board

    board = open_board("virtual")
    try:
        board.record(0.1, strain="virtual")
    except ValueError as e:
        assert 'strain = "virtual": give strain_dir' in str(e)
    else:
        raise AssertionError("strain without strain_dir was accepted")


def test_proprioception_on_the_physics_robot_carries_the_latest_strain_and_its_age() -> None:
    # The physics robot samples its gauges every 24 ms of simulated time (the strain board's line
    # period); each 10 ms proprioception record carries the latest sample at or before its time,
    # so the age lies in [0, 24 ms]. Independent law on the simulated values: at one site the
    # transverse gauge reads -0.39 (Poisson's ratio in the model file) times the axial one.
    from conftest import record_timeout, servo_rest, standing_board

    model = dbot.Model.builtin("drosophibot2")
    plan = dbot.plan(model, slices=50)
    board = standing_board(plan, port="physics")
    board.enter_streaming(timeout_cycles=50)
    recs = []
    for _ in range(30):
        board.send_setpoint(servo_rest(plan, model))
        rec = board.next_proprioception(timeout_s=record_timeout(board))
        assert rec is not None
        recs.append(rec)
    last = recs[-1]
    assert last["strain_names"] == [f"{leg}_{g}" for leg in BOARD_LEGS for g in PER_LEG]
    ages = np.concatenate([r["strain_age_s"] for r in recs])
    assert np.all(ages >= 0.0) and np.all(ages <= 0.024 + 1e-6), ages
    s = last["strain_microstrain"][0]
    assert s.shape == (36,) and np.all(np.isfinite(s))
    assert np.max(np.abs(s)) > 50.0  # the standing legs carry the body
    names = last["strain_names"]
    for leg in BOARD_LEGS:
        axial = s[names.index(f"{leg}_troch_axial")]
        transverse = s[names.index(f"{leg}_troch_transverse")]
        np.testing.assert_allclose(transverse, -0.39 * axial, rtol=1e-9, atol=1e-9)
    latest = board.strain()
    assert latest is not None and latest["names"] == names
    assert latest["time_s"] <= last["time_s"][0] + 1e-9
    board.leave_streaming()


def test_strain_of_a_robot_without_a_body_is_refused_by_name() -> None:
    from conftest import open_board

    board = open_board("virtual")
    try:
        board.strain()
    except dbot.BoardError as e:
        assert "virtual: no simulated strain gauges" in str(e)
    else:
        raise AssertionError("strain() on the virtual robot was accepted")


def test_compare_strain_names_a_folder_that_is_not_a_trial(tmp_path) -> None:
    # The comparison itself (lab::strain_compare) is tested in Rust and through `dbot compare
    # --strain`; here: the binding reaches it and its refusal names the folder.
    try:
        dbot.compare_strain(tmp_path / "nothing", tmp_path)
    except ValueError as e:
        assert str(tmp_path / "nothing") in str(e)
    else:
        raise AssertionError("a missing trial was accepted")


def test_the_standing_prediction_carries_the_weight() -> None:
    # dbot.plan_standing solves the resting posture as a slice: its foot forces hold the body
    # (Newton: vertical sum = m g, horizontal sum = 0), its gauges obey Poisson at each site,
    # and the servo columns are the model's.
    model = dbot.Model.builtin("drosophibot2")
    st = dbot.plan_standing(model)
    f = st["foot_force_n"]
    assert f.shape == (6, 3)
    np.testing.assert_allclose(f.sum(axis=0), [0.0, 0.0, model.mass_kg * 9.81], atol=1e-6 * model.mass_kg * 9.81)
    assert st["angles_rad"].shape == st["torques_nm"].shape == (len(model.servo_joint_names),)
    assert st["gauge_names"] == [f"{leg}_{g}" for leg in BOARD_LEGS for g in PER_LEG]
    s = st["strain_microstrain"]
    names = st["gauge_names"]
    for leg in BOARD_LEGS:
        axial = s[names.index(f"{leg}_troch_axial")]
        np.testing.assert_allclose(s[names.index(f"{leg}_troch_transverse")], -0.39 * axial, rtol=1e-12, atol=1e-9)
    assert np.max(np.abs(s)) > 100.0

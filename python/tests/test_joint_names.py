"""Joint names in telemetry and proprioception (issue #20 item 2), by the rule of ``dbot record``:
each column is the model joint driven by the servo the uploaded table names for it; without a
table this ``Board`` uploaded, the servo the board's joint map (GetJointMap) names for it.

The independent truth is the model file: in ``host/planner/models/drosophibot2.toml`` servo 1
drives ``LF_ThC1``, servo 2 ``LF_ThC3`` (ThC2 has no servo) and servo 3 ``LF_CTr``. A copy of that
file with IDs 1 and 2 swapped plans the same gait, but its table puts servo 2 first; named after
the unchanged model, the first columns must then read ``LF_ThC3, LF_ThC1, LF_CTr``, and named after
the swapped model ``LF_ThC1, LF_ThC3``.
"""

from __future__ import annotations

import pathlib

import pytest

import dbot
from conftest import ROOT, open_board, record_timeout, standing_board, wait_cycles

MODEL_FILE = ROOT / "host/planner/models/drosophibot2.toml"


@pytest.fixture(scope="module")
def swapped_model(tmp_path_factory) -> dbot.Model:
    text = MODEL_FILE.read_text()
    one, two = "servo = { id = 1,", "servo = { id = 2,"
    assert text.count(one) == 1 and text.count(two) == 1, "the model file's servo lines changed"
    text = text.replace(one, "@@").replace(two, one).replace("@@", two)
    path = pathlib.Path(tmp_path_factory.mktemp("swapped")) / "swapped.toml"
    path.write_text(text)
    return dbot.Model.load(path)


def test_telemetry_names_joints_by_the_uploaded_tables_servo_ids(swapped_model) -> None:
    plan = dbot.plan(swapped_model, slices=20)
    board = open_board("virtual")
    # An empty gait store: no joint map, no columns, no names.
    assert board.joint_names == []
    board.upload_plan(0, plan)
    wait_cycles(board, 10)
    rec = board.record(0.1)
    names = rec["joint_names"]
    assert len(names) == rec["present_rad"].shape[1] == 22
    assert names[:3] == ["LF_ThC3", "LF_ThC1", "LF_CTr"]
    assert len(set(names)) == 22 and not any(n.startswith("J") for n in names)
    assert board.joint_names == names
    # Named after the model the table was planned from, the order is the model's own again.
    board.set_model(swapped_model)
    assert board.record(0.1)["joint_names"][:2] == ["LF_ThC1", "LF_ThC3"]
    assert board.joint_names == swapped_model.servo_joint_names


def test_a_board_that_did_not_upload_the_gait_names_joints_by_the_boards_joint_map(
    swapped_model, tmp_path
) -> None:
    store = f"virtual:{tmp_path / 'robot.flash'}"
    first = open_board(store)
    first.upload_plan(0, dbot.plan(swapped_model, slices=20))
    first.close()
    # This Board never saw the table: it asks the board for the table's servo IDs (GetJointMap)
    # and names them through the built-in model, so servo 2 (first in the table) is LF_ThC3.
    board = open_board(store)
    wait_cycles(board, 10)
    names = board.record(0.1)["joint_names"]
    assert names[:3] == ["LF_ThC3", "LF_ThC1", "LF_CTr"]
    assert sorted(names) == sorted(dbot.Model.builtin("drosophibot2").servo_joint_names)


def test_proprioception_carries_the_joint_names(tripod_plan, model) -> None:
    board = standing_board(tripod_plan)
    board.enter_streaming(timeout_cycles=50)
    board.send_setpoint(tripod_plan.angles[0, model.servo_joints])
    rec = board.next_proprioception(timeout_s=record_timeout(board))
    assert rec is not None
    assert rec["joint_names"] == model.servo_joint_names
    assert rec["joint_names"][:2] == ["LF_ThC1", "LF_ThC3"]
    assert len(rec["joint_names"]) == rec["present_rad"].shape[1]
    board.leave_streaming()

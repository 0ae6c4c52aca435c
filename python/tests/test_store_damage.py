"""A damaged gait store is visible from Python (issue #19 item 3) and a `Board` that did not upload
the gait names its joints from the board's joint map (issue #20 item 2).

The independent truths: the store file holds the uploaded table's bytes verbatim (the virtual
robot's flash image, host/board/src/robot/image.rs), so flipping one of them must fail that table's
CRC; random bytes contain no valid commit record (each is guarded by a magic and a CRC-32); and in
``host/planner/models/drosophibot2.toml`` servo 1 drives ``LF_ThC1``, servo 2 ``LF_ThC3``.
"""

from __future__ import annotations

import pathlib
import random

import pytest

import dbot
from conftest import ROOT, open_board, wait_for_state

MODEL_FILE = ROOT / "host/planner/models/drosophibot2.toml"


def _store(tmp_path: pathlib.Path) -> tuple[pathlib.Path, str]:
    path = tmp_path / "robot.flash"
    return path, f"virtual:{path}"


def test_a_flipped_byte_in_the_live_table_is_reported_and_warned_about(model, tmp_path) -> None:
    path, port = _store(tmp_path)
    slow = dbot.plan(model, slices=20).step_table(name="tripod-slow")
    fwd = dbot.plan(model, slices=24).step_table(name="tripod-fwd")
    first = open_board(port)
    first.upload(0, slow)
    first.upload(0, fwd)
    assert first.gaits()[0]["lost"] is None
    assert first.info()["store"] == "ok"
    first.close()

    image = bytearray(path.read_bytes())
    at = bytes(image).find(fwd)
    assert at >= 0, "the uploaded table is in the store file"
    image[at + 200] ^= 0x01
    path.write_bytes(bytes(image))

    board = open_board(port)
    slot = board.gaits()[0]
    assert slot["gait"]["name"] == "tripod-slow"
    assert slot["lost"]["name"] == "tripod-fwd"
    assert slot["lost"]["seq"] == 2
    assert slot["lost"]["reason"] == "table_crc"
    # The lost copy's CRC is the one the table carries in its last 4 bytes.
    assert slot["lost"]["crc"] == int.from_bytes(fwd[-4:], "little")
    # The words `dbot gaits` prints (one function makes them for both doors).
    assert slot["message"] == (
        'slot 0: FELL BACK: the newer copy "tripod-fwd" (seq 2, CRC '
        f'{slot["lost"]["crc"]:#010x}) failed its CRC check and was lost; the older gait plays'
    )
    assert board.info()["store"] == "store damaged: slot 0 fell back"
    assert board.status()["store"] == "store damaged: slot 0 fell back"
    with pytest.warns(UserWarning, match='playing a fallback: slot 0: FELL BACK.*"tripod-fwd"'):
        board.play(0, steps=1)
    wait_for_state(board, ("Standing", "Idle"), 2000)
    # Uploading the table again clears the mark.
    board.upload(0, fwd)
    assert board.gaits()[0]["lost"] is None
    assert board.status()["store"] == "ok"


def test_a_store_of_random_bytes_is_damaged_not_empty(tmp_path) -> None:
    path, port = _store(tmp_path)
    open_board(port).close()
    n = path.stat().st_size
    path.write_bytes(random.Random(19).randbytes(n))
    board = open_board(port)
    slots = board.gaits()
    assert all(s["gait"] is None for s in slots)
    assert all(s["lost"]["reason"] == "record_damaged" for s in slots)
    assert board.info()["store"] == "store damaged: no readable record in any slot"


def test_an_erased_store_is_ok(tmp_path) -> None:
    _, port = _store(tmp_path)
    board = open_board(port)
    assert board.info()["store"] == "ok"
    assert all(s["gait"] is None and s["lost"] is None for s in board.gaits())


def test_a_fresh_board_names_joints_by_the_boards_joint_map(tmp_path_factory, tmp_path) -> None:
    # A model with servos 1 and 2 swapped plans a table whose first joint is servo 2.
    text = MODEL_FILE.read_text()
    one, two = "servo = { id = 1,", "servo = { id = 2,"
    assert text.count(one) == 1 and text.count(two) == 1, "the model file's servo lines changed"
    text = text.replace(one, "@@").replace(two, one).replace("@@", two)
    swapped = tmp_path / "swapped.toml"
    swapped.write_text(text)
    _, port = _store(tmp_path)
    first = open_board(port)
    first.upload_plan(0, dbot.plan(dbot.Model.load(swapped), slices=20))
    first.close()
    # This Board never saw the table; the board reports servo IDs 2, 1, 3, ... for its joints,
    # named through the built-in model: servo 2 drives LF_ThC3, servo 1 LF_ThC1.
    board = open_board(port)
    assert board.joint_names[:3] == ["LF_ThC3", "LF_ThC1", "LF_CTr"]
    assert len(set(board.joint_names)) == 22
    assert board.record(0.1)["joint_names"][:3] == ["LF_ThC3", "LF_ThC1", "LF_CTr"]

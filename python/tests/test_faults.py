"""How the status dict shows a fault: its name, joint, numbers and a sentence (the same text as
`dbot status`), on the in-process virtual robot."""

from __future__ import annotations

import dbot


def test_a_fault_shows_by_name_with_a_sentence_and_clears() -> None:
    board = dbot.Board.open("virtual")
    try:
        assert board.status()["fault"] is None
        board.emergency_stop()
        st = board.status()
        assert st["state"] == "Fault"
        fault = st["fault"]
        assert fault["name"] == "EmergencyStop"
        assert fault["kind"] == "EmergencyStop"
        assert fault["joint"] is None
        assert fault["message"] == "EmergencyStop: emergency stop by the host"
        board.clear_fault()
        assert board.status()["fault"] is None
    finally:
        board.close()

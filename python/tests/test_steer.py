"""The descending command from Python (``Board.steer``) on the physics robot: a steering sweep
whose measured turning rate rises with the commanded heading.

The family: the default plan straight, turning +RANGE and -RANGE rad of yaw per stance
(``rotation_rad``), the same slices, period and leg phases; the board blends them at the heading's
share (protocol::steer). The turning rate is the thorax's yaw (``Board.body()``) over whole steps,
measured from step boundary to step boundary (the playback's step count), after one step at each
new heading for the command to take over at a boundary. Independent truth: the sign of the heading
is the sense of the turn (REP-103: yaw positive left), and the rates are ordered as the headings.
The planned yaw per stance is an upper bound of the walked one (feet slip, the body sways), so the
test asks for the order and for the full turn to be a sizeable part of the plan, not the value
(measured: -0.098, -0.016, 0.040, 0.090 rad per step at -0.06, 0, 0.03, 0.06 rad).
"""

from __future__ import annotations

import math

import pytest

import dbot

#: The family's turn, rad of yaw per stance: about the largest whose first slice the board's
#: switch rule admits beside the straight gait's (lab::steer_blend::RANGE_RAD).
RANGE = 0.06


def wait_step(board: dbot.Board, after: int) -> int:
    """Waits (board time, 10 ms at a time) until the step count passes ``after``."""
    for _ in range(2000):
        pb = board.status()["playback"]
        if pb is not None and pb[1] > after:
            return pb[1]
        board.wait(0.01)
    raise AssertionError(f"no step boundary after step {after}")


def unwrap(a: float) -> float:
    return (a + math.pi) % (2 * math.pi) - math.pi


def test_turning_rate_rises_with_the_commanded_heading() -> None:
    model = dbot.Model.builtin("drosophibot2")
    board = dbot.Board.open("physics")
    for slot, rot in [(0, 0.0), (1, RANGE), (2, -RANGE)]:
        board.upload_plan(slot, dbot.plan(model, slices=20, rotation_rad=rot))
    # A 0.1 rad turn's first slice is too far from the straight gait's for the board to blend
    # (about half of 0.155 rad at a 0.2 rad turn, lab::steer_blend, against 0.0576 rad per bus
    # cycle): refused, saying why.
    board.upload_plan(3, dbot.plan(model, slices=20, rotation_rad=0.1))
    with pytest.raises(Exception, match="slot 3 cannot follow the straight gait: joint"):
        board.set_steer_family(0, 3, 2, 0.1)
    # A heading beyond the family is refused before anything moves, naming the range.
    board.set_steer_family(0, 1, 2, RANGE)
    with pytest.raises(Exception, match="outside the family's range"):
        board.steer(2 * RANGE)
    headings = [-RANGE, 0.0, RANGE / 2, RANGE]
    board.steer(headings[0])
    step = wait_step(board, 0)
    rates = []
    for h in headings:
        board.steer(h)
        # The command takes over at the next boundary; measure over the two steps after it.
        step = wait_step(board, step)
        yaw0 = board.body()["thorax_rpy_rad"][2]
        step = wait_step(board, wait_step(board, step))
        yaw1 = board.body()["thorax_rpy_rad"][2]
        rates.append(unwrap(yaw1 - yaw0) / 2)
    board.stop()
    assert board.status()["fault"] is None
    board.close()
    print("heading (rad) -> yaw per step (rad):", list(zip(headings, rates)))
    assert all(b > a for a, b in zip(rates, rates[1:])), rates
    assert rates[0] < 0 < rates[-1], rates
    # The full turn walks a sizeable part of the planned RANGE per stance (ESTIMATE of the floor).
    assert rates[-1] > 0.25 * RANGE, rates

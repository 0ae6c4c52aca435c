"""bench/step_profile.py's `instructions` mode (docs/performance.md, "The simulated wire's byte
handling"): its totals of a callgrind_annotate listing, against the listing's numbers by hand."""

from __future__ import annotations

import importlib.util
import pathlib

import pytest

BENCH = pathlib.Path(__file__).resolve().parents[2] / "bench" / "step_profile.py"

# The lines it reads, cut from a real `callgrind_annotate --inclusive=yes --tree=calling`.
LISTING = """\
--------------------------------------------------------------------------------
3,621,365,904 (100.0%)  PROGRAM TOTALS
3,596,623,087 (97.66%)  *  ???:board::robot::board::VirtualRobot<S>::cycle [/x/_native.abi3.so]
3,308,855,960 (91.37%)  >   ???:<physics::robot::PhysicsRobot as board::robot::servos::ServoDynamics>::before_cycle (1,385x) [/x/_native.abi3.so]
  263,108,016 ( 7.14%)  >   ???:dynamixel::sim::wire::SimWire::block_on (1,385x) [/x/_native.abi3.so]
3,236,090,817 (89.36%)  *  ???:physics::plant::Plant::step [/x/_native.abi3.so]
3,188,906,817 (88.06%)  >   ???:mj_step (13,840x) [/x/libmujoco.so.3.17.0]
3,188,906,817 (88.06%)  *  ???:mj_step [/x/libmujoco.so.3.17.0]
"""


def load():
    spec = importlib.util.spec_from_file_location("step_profile", BENCH)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_instructions_per_bus_cycle(capsys: pytest.CaptureFixture[str]) -> None:
    load().instructions(LISTING.splitlines())
    out = capsys.readouterr().out
    # 3 621 365 904 / 1385 = 2 614 704.6; 3 188 906 817 / 1385 = 2 302 459.8;
    # the rest 432 459 087 / 1385 = 312 244.8 (floored).
    assert "1385 bus cycles" in out
    assert "| 3,621,365,904 | 2,614,704 |" in out
    assert "| 3,188,906,817 | 2,302,459 |" in out
    assert "| 432,459,087 | 312,244 |" in out


def test_a_listing_without_the_cycles_is_refused() -> None:
    with pytest.raises(SystemExit, match="not callgrind_annotate"):
        load().instructions(["3,621,365,904 (100.0%)  PROGRAM TOTALS"])

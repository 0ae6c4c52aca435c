"""The SNS controller example (python/examples/sns_walk.py), closed loop through `DbotEnv`:

* its neurons are leaky integrators with graded synapses: steady states checked against the hand
  solution of C dU/dt = -G_m U + g (E - U) + I (U = (I + g E) / (G_m + g));
* on the physics robot, its LOAD neurons fed by the legs' strain gauges (the trochanteral and
  femoral CS fields), it walks the planned tripod's distance (to 60 %) on flat ground and up a
  5 degree incline without a fall or a fault (uphill it is marginal: see the parameters below),
  and the feet touch the ground when its network says stance (measured contact against the
  controller's stance); the strain it senses is a load signal: its LOAD neurons fire in the
  measured stance, not in swing; its climb is pinned (walks up 6 degrees, falls at 7);
* the same script runs on the emulated board (the release firmware in the RP2040 emulator), where
  there is no strain, on the servo load (the fallback).
"""

from __future__ import annotations

import importlib.util
import pathlib

import numpy as np
import pytest

EXAMPLE = pathlib.Path(__file__).resolve().parents[1] / "examples" / "sns_walk.py"


@pytest.fixture(scope="module")
def sns():
    spec = importlib.util.spec_from_file_location("sns_walk", EXAMPLE)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_neurons_settle_where_the_membrane_equation_says(sns) -> None:
    # Two neurons: 0 tonic (I = 20 nA, G_m = 1 uS: U = 20 mV = R, fully active); 1 tonic
    # 20 nA and inhibited by 0 through g_max = 2 uS, E = -40 mV: U = (20 - 80) / 3 = -20 mV.
    net = sns.Network(
        c_nf=np.array([5.0, 5.0]),
        gm_us=np.ones(2),
        i_app_na=np.array([20.0, 20.0]),
        g_max_us=np.array([[0.0, 0.0], [2.0, 0.0]]),
        e_mv=np.array([[0.0, 0.0], [-40.0, 0.0]]),
        u_mv=np.zeros(2),
    )
    for _ in range(2000):
        net.step(0.001, np.zeros(2))
    assert net.u_mv == pytest.approx([20.0, -20.0], abs=1e-6)
    # Half active (U = 10 mV) through a graded synapse: g = 2 x 0.5 = 1 uS, E = 134 mV onto a
    # silent neuron: U = 134 / 2 = 67 mV.
    net = sns.Network(np.array([5.0, 5.0]), np.ones(2), np.array([10.0, 0.0]),
                      np.array([[0.0, 0.0], [2.0, 0.0]]), np.array([[0.0, 0.0], [134.0, 0.0]]),
                      np.zeros(2))
    for _ in range(2000):
        net.step(0.001, np.zeros(2))
    assert net.u_mv == pytest.approx([10.0, 67.0], abs=1e-6)


@pytest.mark.parametrize(
    ("scene", "cycles", "at_least_m"),
    # The plan moves the thorax 0.085 m per tripod stance, two per cycle (dbot.plan's default,
    # servo-safe: 2.5 s cycles): 3 cycles are 0.51 m, 4 are 0.68 m. ESTIMATE of what is fair:
    # 60 % flat; up the incline (gravity pulls back) a third of that. Uphill the controller is
    # marginal (measured, 4 cycles, after the body was stepped on simulated time alone): with
    # strain feedback it walks at 3, 4, 5 and 6 degrees (0.35, 0.43, 0.54, 0.17 m) and falls at
    # 7, 8, 10 and 12; at 6 it is on a knife edge (5.9999 degrees walks 0.23 m, 6.0001 falls, its
    # feet agree with its network only 70 % of the time), at 5 it is not (4.9999 and 5.0001
    # degrees walk 0.53 and 0.54 m). So 5 degrees tests that it climbs; the pins below say how
    # steep. Why the steepest climb moved from 10 to 6 degrees once: docs/validation.md, "The SNS
    # example's climb".
    [("flat", 3, 0.6 * 0.51), ("incline:5", 4, 0.2 * 0.68)],
)
def test_it_walks_a_set_distance_without_a_fall(sns, scene, cycles, at_least_m) -> None:
    rec = sns.run(f"physics:{scene}", cycles)
    assert str(rec["feedback"]) == "strain"
    assert str(rec["ended"]) == "no"
    assert len(rec["time_s"]) == round(cycles * 2.5 / 0.01)
    walked = rec["x_m"][-1] - rec["x_m"][0]
    assert walked > at_least_m, walked
    # After the first cycle, a foot the network holds in stance touches the ground, and a
    # swinging one is lifted, three quarters of the time or more (touch-down and lift-off take
    # a few bus cycles; on the incline the hind feet drag).
    settled = slice(250, None)
    agree = np.mean(rec["contact"][settled] == rec["stance"][settled])
    assert agree > 0.75, agree
    # The gauges signal load: each leg's LOAD neuron is more active while its foot is measured
    # on the ground than while it is in the air (the cuticle strains under the body's weight).
    names = list(rec["neurons"])
    for i, leg in enumerate(rec["legs"]):
        load = rec["activity"][settled, names.index(f"{leg}_LOAD")]
        down = rec["contact"][settled][:, i]
        assert load[down].mean() > load[~down].mean(), leg


@pytest.mark.parametrize(("degrees", "walks"), [(6, True), (7, False)])
def test_its_climb_is_the_pinned_one(sns, degrees, walks) -> None:
    # Pinned (measured, deterministic): with strain feedback it walks 4 cycles up 6 degrees and
    # falls at 7 (and at 8, 10, 12). A change that moves the physics robot or the controller and
    # flips either fails here and re-measures the climb (the test above's comment), with the
    # reason in its commit.
    rec = sns.run(f"physics:incline:{degrees}", 4)
    assert str(rec["feedback"]) == "strain"
    assert (str(rec["ended"]) == "no") == walks, (degrees, str(rec["ended"]))


def test_the_same_script_runs_on_the_emulated_board(sns, emulator_port) -> None:
    rec = sns.run(emulator_port, cycles=1.0, max_steps=25)
    assert str(rec["feedback"]) == "load"  # no strain on a board: the servo load
    assert str(rec["ended"]) == "no"
    assert rec["activity"].shape == (25, 30)
    assert rec["x_m"].size == 0 and rec["contact"].size == 0
    # Tripod A started its swing: its swing neurons are active, B's stance neurons too.
    names = list(rec["neurons"])
    assert rec["activity"][-1, names.index("LF_SW")] > 0.9
    assert rec["activity"][-1, names.index("RF_ST")] > 0.9

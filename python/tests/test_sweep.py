"""`dbot.sweep`: rollouts of planned gaits on the physics robot, swept in one process, over a
process pool, on a local Ray cluster and against that cluster by its address (a separate
driver process, as a machine elsewhere would join), with the same rows from every backend (the
rollouts are deterministic); the figures respond to the parameters as physics says (twice the
stride, about twice the distance, and more work); the energy is the sum of |torque x velocity| x dt
computed by hand on a synthetic rollout, its torque the load registers' ESTIMATE of the e-manual's
units (MX-28: 0.1 % of the stall torque; MX-64: 3.36 mA per unit times stall torque over stall
current); the Pareto front of hand-made rows is the hand-found one; and
`gymnasium.vector.AsyncVectorEnv` runs `DbotEnv` in worker processes with the same observations
as one environment.
"""

from __future__ import annotations

import json
import subprocess
import sys

import gymnasium as gym
import numpy as np
import pytest

from dbot.env import DbotEnv
import dbot
from dbot.sweep import gait_rollout, grid, mechanical_energy_j, pareto, sweep, table
from conftest import need_module

POINTS = grid(translation_m=[0.04, 0.085], cycles=[1.5])


@pytest.fixture(scope="module")
def serial_rows():
    return sweep(gait_rollout, POINTS)


def test_grid_is_every_combination() -> None:
    assert grid(a=[1, 2], b=["x"]) == [{"a": 1, "b": "x"}, {"a": 2, "b": "x"}]


def test_the_figures_follow_the_stride(serial_rows) -> None:
    short, long = serial_rows
    assert not short["fell"] and not long["fell"]
    # 0.085 / 0.04 = 2.1 times the stride: between 1.6 and 2.6 times the distance (the first
    # step starts from standing, and the feet slip a little more at the longer stride).
    ratio = long["distance_m"] / short["distance_m"]
    assert 1.6 < ratio < 2.6, ratio
    for r in serial_rows:
        assert 0.0 <= r["slip_m"] < r["distance_m"]
        assert 0.0 < r["tracking_rad"] < 0.1
        assert r["energy_j"] > 0.0
    # The longer stride moves the joints further in the same time against the same weight.
    assert long["energy_j"] > short["energy_j"], (short["energy_j"], long["energy_j"])
    assert "| translation_m | cycles | distance_m |" in table(serial_rows)


def test_energy_of_a_synthetic_rollout_is_the_hand_sum() -> None:
    # Two samples of two joints, 10 ms apart: |1 x 3| + |-2 x 1| + |0.5 x -4| + |0 x 7| = 7 W s
    # per second of samples, times 0.01 s = 0.07 J.
    tau = np.array([[1.0, -2.0], [0.5, 0.0]])
    omega = np.array([[3.0, 1.0], [-4.0, 7.0]])
    assert mechanical_energy_j(tau, omega, 0.01) == pytest.approx(0.07, abs=1e-15)
    with pytest.raises(ValueError, match=r"torque_nm has shape \(2, 2\), velocity_rad_s \(2,\)"):
        mechanical_energy_j(tau, omega[0], 0.01)


def test_the_torque_estimate_from_the_load_registers_is_the_e_manuals() -> None:
    model = dbot.Model.builtin("drosophibot2")
    stall = np.asarray(model.servo_stall_torques_nm)
    mx28, mx64 = int(np.argmax(stall == 2.5)), int(np.argmax(stall == 6.0))
    load = np.zeros((2, stall.size))
    load[0, mx28], load[1, mx28] = 400, -1000  # 40 % and -100 % of the MX-28's 2.5 N m
    load[0, mx64] = 100  # 100 x 3.36 mA = 0.336 A, x 6.0 N m / 4.1 A
    tau = model.load_torques_nm(load)
    assert tau.shape == load.shape
    assert tau[0, mx28] == pytest.approx(1.0, rel=1e-6)
    assert tau[1, mx28] == pytest.approx(-2.5, rel=1e-6)
    assert tau[0, mx64] == pytest.approx(0.336 * 6.0 / 4.1, rel=1e-6)
    # Integer registers as proprioception gives them, the same.
    np.testing.assert_array_equal(model.load_torques_nm(load.astype(np.int32)), tau)
    name = model.servo_joint_names[3]
    with pytest.raises(ValueError, match=f"load_raw 0.5 of {name} is not a register value"):
        bad = np.zeros(stall.size)
        bad[3] = 0.5
        model.load_torques_nm(bad)
    with pytest.raises(ValueError, match="its last axis must be the 22 servo joints"):
        model.load_torques_nm(np.zeros(21))


def test_pareto_front_of_hand_made_rows() -> None:
    rows = [
        {"d": 1.0, "s": 0.1},  # front
        {"d": 2.0, "s": 0.3},  # front
        {"d": 1.5, "s": 0.35},  # dominated by the second
        {"d": 3.0, "s": 0.2, "fell": True},  # fell: left out
        {"d": 0.5, "s": 0.05},  # front
    ]
    assert pareto(rows, "d", "s") == [4, 0, 1]


def test_processes_and_ray_give_the_serial_rows(serial_rows) -> None:
    ray = need_module("ray")  # the `test` extra and scripts/setup.d/40-python.sh install it
    assert sweep(gait_rollout, POINTS, backend="processes", processes=2) == serial_rows
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        assert sweep(gait_rollout, POINTS, backend="ray") == serial_rows
        # The same code against the cluster's address, from another driver process.
        address = ray.get_runtime_context().gcs_address
        code = (
            "import json, sys; from dbot.sweep import gait_rollout, sweep; "
            f"print(json.dumps(sweep(gait_rollout, {POINTS!r}, backend='ray', address={address!r})))"
        )
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                             timeout=300, check=True)
        assert json.loads(out.stdout.strip().splitlines()[-1]) == serial_rows
    finally:
        ray.shutdown()


def test_async_vector_env_matches_one_environment() -> None:
    n, steps = 2, 20
    venv = gym.vector.AsyncVectorEnv([lambda: DbotEnv("physics", max_episode_steps=50)] * n)
    obs, _ = venv.reset(seed=[4, 4])
    one = DbotEnv("physics", max_episode_steps=50)
    ref, _ = one.reset(seed=4)
    rng = np.random.default_rng(1)
    for _ in range(steps):
        a = one.rest_rad + rng.uniform(-0.03, 0.03, size=one.rest_rad.size)
        obs, *_ = venv.step(np.stack([a] * n))
        ref, *_ = one.step(a)
    for k in ref:
        for i in range(n):
            assert obs[k][i].tobytes() == ref[k].tobytes(), k
    venv.close()
    one.close()


def test_plot_pareto_writes_the_plot_and_returns_the_front(tmp_path) -> None:
    from dbot.sweep import plot_pareto

    rows = [{"d": 1.0, "s": 0.1}, {"d": 2.0, "s": 0.3}, {"d": 1.5, "s": 0.35}]
    png = tmp_path / "pareto.png"
    assert plot_pareto(rows, "d", "s", str(png)) == [0, 1]
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"

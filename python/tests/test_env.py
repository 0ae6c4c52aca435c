"""`dbot.env.DbotEnv`, the Gymnasium environment over a robot with the firmware in the loop:

* Gymnasium's own conformance checker (`gymnasium.utils.env_checker.check_env`, an external
  reference) passes on the physics robot;
* a step's observation is the row of the record it took, after one setpoint per bus cycle;
* deterministic: the same seed and actions give bit-identical observations (two environments,
  each its own physics robot);
* reset leaves the robot standing in its resting posture, streaming, no step played, and a
  standing robot is not a fall; holding the rest posture, the thorax stays at its height;
* the strain in the observation is the body's: standing with the torque bias, the 36 gauges read
  what the planner predicts for the standing robot (`dbot.plan_standing`, the prediction of the
  `strain` block of docs/validation.md, where the simulated gauges are 2.46 % RMS off it), and
  each reading is at most 24 ms old (the sampling period);
* with a plan given, `info` holds the plan's predicted strain at the step phase (time since reset
  over the period), linear between slices: checked against `Plan.strain` by hand;
* the same class opens on the emulated board's pty (the release firmware image in the RP2040
  emulator, conftest.py's `emulator_port`) with the same action space and the observation space
  without strain (a board streams none), and its `info` holds only what a board knows (no `body`).
"""

from __future__ import annotations

import pathlib

import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import dbot
from dbot.env import DbotEnv
from traces import assert_bit_identical

ROOT = pathlib.Path(__file__).resolve().parents[2]

STRAIN_KEYS = {"strain_microstrain", "strain_age_s"}


def test_check_env_passes_on_the_physics_robot() -> None:
    env = DbotEnv("physics", max_episode_steps=20, render_mode="rgb_array")
    check_env(env)
    env.close()


def test_check_env_passes_with_torques_in_the_action() -> None:
    env = DbotEnv("physics:blocks:3", max_episode_steps=20, torques=True)
    check_env(env, skip_render_check=True)
    # Bounded by each servo's stall torque (e-manual, 12 V): MX-28 2.5 N m, MX-64 6.0 N m.
    high = env.action_space["torques_nm"].high
    assert set(np.round(high, 6)) <= {2.5, 6.0} and np.array_equal(high, -env.action_space["torques_nm"].low)
    env.close()


def test_a_torque_in_the_action_biases_the_commanded_angle_by_torque_over_stiffness() -> None:
    # The firmware's torque bias: goal = angle + torque / stiffness (protocol JointSetpoint).
    k = 10.0
    env = DbotEnv("physics", max_episode_steps=20, torques=True, stiffness_nm_rad=k)
    env.reset(seed=0)
    torque = np.zeros(len(env.joint_names))
    torque[0], torque[5] = 0.5, -1.2
    # The board moves a goal at most a servo's one-cycle move per cycle (firmware::goal_step:
    # 37 ticks on an MX-28, 43 on an MX-64 at 100 Hz): -0.12 rad is 78.2 ticks, reached on the
    # third cycle at the latest (2 x 37 = 74 falls short). One env step is one cycle here.
    for _ in range(3):
        env.step({"angles_rad": env.rest_rad, "torques_nm": torque})
    shift = np.asarray(env.last_record["commanded_rad"][0]) - env.rest_rad
    # 0.5 / 10 = 0.05 rad and -1.2 / 10 = -0.12 rad, within 2 %: the board holds the stiffness
    # as the servo's nearest Position P Gain (host/physics/src/servo.rs), about 1 % off here.
    assert abs(shift[0] / 0.05 - 1) < 0.02 and abs(shift[5] / -0.12 - 1) < 0.02, shift[[0, 5]]
    assert np.max(np.abs(np.delete(shift, [0, 5]))) < 3e-4
    env.close()


def test_a_step_observes_the_record_it_took_and_sends_one_setpoint_per_cycle() -> None:
    """`Board.stream_step`, `DbotEnv.step`'s one call: its observation is the last record's row
    as `next_proprioception` gives it (`last_stream_record`), each value the same double, after
    one setpoint per cycle (the sequence numbers the record echoes count them)."""
    env = DbotEnv("physics", max_episode_steps=20, cycles_per_step=3)
    env.reset(seed=0)
    seq0 = int(env.last_record["setpoint_seq"][0])
    obs, *_ = env.step(env.rest_rad)
    rec = env.last_record
    assert int(rec["setpoint_seq"][0]) == seq0 + 3
    for key in ("present_rad", "velocity_rad_s", "load_raw", "strain_microstrain"):
        assert np.array_equal(obs[key], np.asarray(rec[key][0], dtype=np.float64)), key
    assert obs["setpoint_age"].tolist() == [float(rec["setpoint_age"][0])]
    assert obs["strain_age_s"].tolist() == [float(rec["strain_age_s"][0])]
    with pytest.raises(ValueError, match="cycles = 0: give 1 or more"):
        env.board.stream_step(env.rest_rad, cycles=0)
    env.close()


def test_render_draws_the_robot_on_its_blocks_and_an_episode_becomes_a_gif(tmp_path) -> None:
    env = DbotEnv("physics", max_episode_steps=30, render_mode="rgb_array")
    env.reset(seed=0, options={"scene": "blocks:5"})
    for _ in range(10):
        env.step(env.rest_rad)
    frame = env.render()
    assert frame.shape == (420, 1200, 3) and frame.dtype == np.uint8
    # The drawing's colours: the foot red of stance feet (report/src/robot/views.rs FOOT) and,
    # from above, the shaded blocks (not white) fill most of the top view's plot.
    assert np.any(np.all(frame == [214, 39, 40], axis=-1))
    top = frame[80:330, 60:380]
    assert np.mean(np.any(top != 255, axis=-1)) > 0.8
    gif = tmp_path / "episode.gif"
    assert env.write_gif(str(gif), every=2) == 6
    assert gif.read_bytes()[:6] == b"GIF89a"
    env.close()


def test_same_seed_and_actions_give_bit_identical_observations() -> None:
    runs = []
    for _ in range(2):
        env = DbotEnv("physics", max_episode_steps=100)
        obs, _ = env.reset(seed=3)
        low, high = env.action_space.low, env.action_space.high
        rest = env.rest_rad
        actions = np.random.default_rng(7).uniform(-0.05, 0.05, size=(40, rest.size)) + rest
        trace = [obs]
        for a in actions:
            obs, *_ = env.step(np.clip(a, low, high))
            trace.append(obs)
        runs.append(trace)
        env.close()
    assert_bit_identical(runs)


def test_reset_stands_streaming_in_the_resting_posture() -> None:
    env = DbotEnv("physics", max_episode_steps=50)
    obs, info = env.reset(seed=0)
    assert env.board is not None
    st = env.board.status()
    assert st["state"] == "Streaming"
    # Nothing was played: the playback position is None or at its start (no step completed).
    assert st["playback"] is None or st["playback"][0] == 0, st["playback"]
    assert obs["setpoint_age"][0] <= 1
    body = info["body"]
    h0 = body["thorax_position_m"][2]
    # Holding the rest posture for 1 s: the robot stands (no fall, no fault) at its height.
    for _ in range(100):
        obs, reward, terminated, truncated, info = env.step(env.rest_rad)
        assert not terminated
    h1 = info["body"]["thorax_position_m"][2]
    assert abs(h1 - h0) < 2e-3, (h0, h1)
    # Standing still, forward progress (the default reward) is about nothing.
    assert abs(reward) < 1e-3
    # Present angles follow the held posture up to each servo's deflection under the body's
    # weight: its standing load / its stiffness (the planner's statics, dbot.plan_standing, over
    # the stiffness the board holds), plus 0.01 rad for the body's sway and the settling of the
    # stance. Before (issue 43) the bound was 0.17 rad, the stall torque over the stiffness, that
    # no servo under this body comes near.
    load = np.abs(dbot.plan_standing(dbot.Model.builtin("drosophibot2"))["torques_nm"])
    k = env.board.settings()["stiffness_nm_rad"]
    bound = load / k + 0.01
    deflection = np.abs(obs["present_rad"] - env.rest_rad)
    assert np.all(deflection < bound), (deflection, bound)
    assert np.max(bound) < 0.17
    assert "body" in info and info["state"] == "Streaming"
    env.close()


def test_a_fall_terminates() -> None:
    # The rule: thorax below a fraction of its height at reset (default half) or tilted over 30
    # degrees ends the episode; at a fraction of 2 a standing robot has "fallen".
    env = DbotEnv("physics", max_episode_steps=10, fall_height_fraction=2.0)
    env.reset(seed=0)
    _, _, terminated, _, _ = env.step(env.rest_rad)
    assert terminated
    env.close()


def test_standing_with_the_bias_the_observed_strain_is_what_the_planner_predicts() -> None:
    # The setpoint of dbot.plan_standing (its angles, its torques as the bias) on the physics
    # robot, as the `strain` block of docs/validation.md stands it (there 2.46 % RMS off the
    # prediction, worst gauge 15 microstrain of 470): here the bias comes on after reset's settle
    # rather than as gravity ramps in, so the feet took their load unbiased first; measured
    # 1.36 % RMS, worst gauge 8.4 microstrain of 470.6 (-s prints it). Bound: 5 % RMS and 30
    # microstrain, host/physics/tests/integration/strain_standing.rs's bounds.
    model = dbot.Model.builtin("drosophibot2")
    standing = dbot.plan_standing(model)
    env = DbotEnv("physics", model=model, max_episode_steps=300, torques=True)
    assert env.has_strain and env.strain_names == standing["gauge_names"]
    assert len(env.strain_names) == 36 and env.strain_names[0] == "LH_troch_axial"
    assert STRAIN_KEYS <= set(env.observation_space.spaces)
    obs, _ = env.reset(seed=0)
    # The resting posture the environment holds is the planner's standing one (to the wire's
    # resolution and the few mrad the joints settle by when torque comes on).
    assert np.max(np.abs(env.rest_rad - standing["angles_rad"])) < 0.01
    action = {"angles_rad": standing["angles_rad"], "torques_nm": standing["torques_nm"]}
    ages = []
    for _ in range(200):
        obs, _, terminated, _, _ = env.step(action)
        assert not terminated
        ages.append(obs["strain_age_s"][0])
    assert env.observation_space.contains(obs)
    assert 0.0 <= min(ages) and max(ages) <= 0.024 + 1e-9, (min(ages), max(ages))
    sim, pred = obs["strain_microstrain"], standing["strain_microstrain"]
    rel = np.sqrt(np.mean((sim - pred) ** 2) / np.mean(pred**2))
    worst = np.max(np.abs(sim - pred))
    print(f"standing, bias on: {100 * rel:.2f} % RMS, worst {worst:.1f} microstrain of {np.max(np.abs(pred)):.1f}")
    assert rel < 0.05, rel
    assert worst < 30.0, worst
    assert np.max(np.abs(pred)) > 100.0  # not a trivial agreement
    env.close()


def test_info_holds_the_plans_predicted_strain_at_the_step_phase() -> None:
    model = dbot.Model.builtin("drosophibot2")
    plan = dbot.plan(model, slices=50)
    # servo-safe: a 2.5 s period in 50 slices, a slice every 50 ms = 5 bus cycles of 10 ms.
    assert plan.period_s == pytest.approx(2.5) and plan.slices == 50
    predicted = plan.strain
    env = DbotEnv("physics", model=model, gait=plan, max_episode_steps=20)
    _, info = env.reset(seed=0)
    assert info["plan_phase"] == 0.0
    np.testing.assert_allclose(info["predicted_strain_microstrain"], predicted[0], rtol=1e-12)
    for _ in range(7):
        _, _, _, _, info = env.step(env.rest_rad)
    # 7 cycles = 70 ms = 1.4 slices: 0.6 of slice 1 and 0.4 of slice 2.
    assert info["plan_phase"] == pytest.approx(0.07 / 2.5, abs=1e-9)
    np.testing.assert_allclose(
        info["predicted_strain_microstrain"], 0.6 * predicted[1] + 0.4 * predicted[2], rtol=1e-6, atol=1e-6
    )
    # Past the period's end it wraps: phase 0.99 lies between the last slice and slice 0.
    np.testing.assert_allclose(env.predicted_strain(0.99), 0.5 * predicted[49] + 0.5 * predicted[0], atol=1e-9)
    env.close()
    # Without a plan, no prediction.
    env = DbotEnv("physics", max_episode_steps=5)
    _, info = env.reset(seed=0)
    assert "predicted_strain_microstrain" not in info and "plan_phase" not in info
    env.close()


def test_the_same_class_runs_on_the_emulated_board(emulator_port) -> None:
    phys = DbotEnv("physics", max_episode_steps=5)
    board_env = DbotEnv(emulator_port, max_episode_steps=5)
    assert board_env.action_space == phys.action_space
    # A board streams no strain: the physics robot's space without the gauges.
    assert phys.has_strain and not board_env.has_strain
    assert set(phys.observation_space.spaces) - set(board_env.observation_space.spaces) == STRAIN_KEYS
    for key, space in board_env.observation_space.spaces.items():
        assert space == phys.observation_space[key], key
    obs, info = board_env.reset(seed=0)
    assert board_env.observation_space.contains(obs)
    assert set(info) == {"time_s", "state"}
    assert board_env.board is not None and board_env.board.kind == "serial"
    for _ in range(3):
        obs, reward, terminated, truncated, info = board_env.step(board_env.rest_rad)
        assert board_env.observation_space.contains(obs)
        assert "body" not in info and reward == 0.0
        assert not terminated
    board_env.close()
    phys.close()


def test_torques_reach_the_emulated_board_as_a_bias(emulator_port) -> None:
    # The same Dict action on the release firmware image: its commanded angle is the target plus
    # torque / stiffness, as on the physics robot (2 %: the P gain's quantisation).
    k = 10.0
    env = DbotEnv(emulator_port, max_episode_steps=10, torques=True, stiffness_nm_rad=k)
    env.reset(seed=0)
    torque = np.zeros(len(env.joint_names))
    torque[3] = 0.8
    for _ in range(3):
        obs, _, terminated, _, _ = env.step({"angles_rad": env.rest_rad, "torques_nm": torque})
        assert not terminated
    shift = np.asarray(env.last_record["commanded_rad"][0]) - env.rest_rad
    assert abs(shift[3] / 0.08 - 1) < 0.02, shift[3]
    assert np.max(np.abs(np.delete(shift, 3))) < 3e-4
    env.close()


def test_a_physics_port_naming_a_model_file_stands_on_that_files_servos(tmp_path) -> None:
    """``physics:SCENE+model:FILE`` runs the body of a model file (e.g. the one ``dbot identify``
    fitted). Hooke's law is the truth: with every servo's P gain divisor doubled (256 for the
    e-manual's 128: half the stiffness for the same register) the joints standing under the same
    weight deflect about twice as far from the held posture as the built-in body's."""
    text = (ROOT / "host/planner/models/drosophibot2.toml").read_text()
    assert text.count("p_gain_divisor = 128.0") == 2
    soft = tmp_path / "soft.toml"
    soft.write_text(text.replace("p_gain_divisor = 128.0", "p_gain_divisor = 256.0"))

    def standing_deflection(port: str) -> float:
        env = DbotEnv(port, max_episode_steps=60, render_mode="rgb_array")
        assert env.physics
        obs, _ = env.reset(seed=0)
        for _ in range(50):
            obs, _, terminated, _, info = env.step(env.rest_rad)
            assert not terminated, port
        assert info["state"] == "Streaming"
        assert env.render().shape[2] == 3
        env.close()
        return float(np.sum(np.abs(obs["present_rad"] - env.rest_rad)))

    builtin = standing_deflection("physics:flat+floor")
    fitted = standing_deflection(f"physics:flat+floor+model:{soft}")
    assert 1.6 * builtin < fitted < 2.5 * builtin, (builtin, fitted)

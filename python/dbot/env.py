"""A Gymnasium environment over a robot with the firmware in the loop: :class:`DbotEnv`.

The same class drives the physics robot (``port="physics[:SCENE]"``: the firmware library over the
simulated bus moving a MuJoCo body, time passing only while the environment waits, so it runs much
faster than real time and is deterministic) and a board port (a real board, or the RP2040
emulator's pseudo-terminal), with the same spaces. It uses only the typed :class:`dbot.Board`.

``reset`` puts the robot in its resting posture, streaming, with no played step:

1. (physics) the robot is opened afresh on the scene: its body stands in the planner's stance
   with its servos off; (a board) a fault is cleared and a walk or stream is stopped.
2. A step table of the default plan is uploaded into slot 0 (the board learns its joint map,
   calibration, limits and stiffness from it; nothing is played), then the stiffness option.
3. Torque on: the firmware holds the present posture (Idle -> Standing; on the physics robot gravity
   ramps in over 1 s and the body settles for ``settle_s``).
4. ``enter_streaming``; the first setpoint is the held posture itself.

``step(action)`` sends the 22 joint targets (rad, ``Model.servo_joint_names`` order, bounded by the
model's joint limits) for each of ``cycles_per_step`` bus cycles and returns the last cycle's
proprioception. With ``torques=True`` the action is a ``Dict``: ``angles_rad`` (the targets) and
``torques_nm`` (22, N m, each bounded by its servo's stall torque, ``Model.servo_stall_torques_nm``:
2.5 N m for an MX-28, 6.0 for an MX-64 at 12 V), the torque feed-forward of the board's streaming
setpoint (``JointSetpoint::torque``, mN m on the wire): the firmware adds ``torque / stiffness`` to
the angle, the same torque bias it applies to a played gait. Observation (a ``Dict``; what the board streams, so a controller tuned here runs on
a board): ``present_rad`` (22, rad), ``velocity_rad_s`` (22, rad/s), ``load_raw`` (22, register 126
as read: MX-28 load in 0.1 % of its maximum, MX-64 current in about 3.36 mA), ``setpoint_age`` (1,
bus cycles since the setpoint in use arrived). Where the port streams strain (the physics robot
with a model that has gauges, Drosophibot II's 36), also ``strain_microstrain`` (one per gauge,
``strain_names`` order: the strain board's channel order, ``LH_troch_axial`` first; the latest
sample, microstrain, tension positive; bounded by +-1e6, a strain of 1, which no intact segment
reaches: the bound only says the reading is finite and signed) and ``strain_age_s`` (1, s since
that sample was taken: the gauges are sampled every 24 ms, the strain board's line period, so 0
to 0.024; bounded by 1 s). A board port keeps the space without them (this class has no strain
board beside a board yet): a controller knows by ``env.has_strain`` (or ``"strain_microstrain" in
env.observation_space.spaces``) and falls back on ``load_raw``.

``info`` on the physics robot: ``body`` (``Board.body()``: thorax pose and velocity, foot forces,
contact and slip, simulated time), ``time_s``, ``state``; on a board only what a board knows:
``time_s`` (its proprioception's clock) and ``state``. With a plan known (``gait=`` given) and
gauges in its model, on any port (the host computes it from the plan, not from the body), also
``plan_phase`` (fraction of the period: the time since reset over the plan's period, modulo 1,
i.e. where the plan played open loop from its slice 0 at reset is now) and
``predicted_strain_microstrain`` (the plan's predicted strain, ``Plan.strain``, at that phase,
linear between slices; ``gait.gauge_names`` order, which is ``strain_names`` on the physics
robot); without a plan, neither. For the standing robot
the prediction is ``dbot.plan_standing(model)["strain_microstrain"]``.

Rendering: ``render_mode="rgb_array"`` gives the demo's walk drawing of the present pose (top,
side and front views on the scene's ground, blocks included; a ball is not drawn), 1200 x 420
pixels, the camera centred on the thorax at the scale fixed at reset; on a board the thorax is
drawn upright at the origin (a board cannot see its body). ``write_gif(path)`` writes the episode
so far as a GIF with the camera following the thorax. MuJoCo's own renderer is not used.

Scenes (``physics:SCENE`` or the ``scene`` reset option): ``flat``, ``incline:DEG``, ``ball``,
``ball-fixed``, ``blocks[:SEED[:HEIGHT_M[:SIZE_M[:GAPS]]]]`` (seeded random block heights; the
planner plans for flat, incline and ball only).

Termination: a firmware fault (streaming stops: the state is ``Fault``), or on the physics robot a
fall: thorax below ``fall_height_fraction`` (default 0.5) of its height at reset, or tilted more
than ``fall_tilt_rad`` (default 30 degrees; the rule of ``physics::Figures::verdict``). Truncation:
``max_episode_steps`` steps. Default reward: forward progress, the thorax's world x advance in this
step, m (0 on a board, which cannot see its body); pass ``reward=`` to replace it.

Many physics robots at once: :class:`VectorEnv` (python/dbot/vector_env.py, re-exported here), N
of this class's physics robot stepped on Rust threads, each equal to ``DbotEnv`` bit for bit;
``gymnasium.make_vec("dbot/Physics-v0", num_envs=N)`` builds one.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Callable, Mapping

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from ._native import (
    Board,
    EnvStepper,
    Model,
    Plan,
    camera_half_extent,
    plan,
    render_pose,
    write_walk_gif,
)

if TYPE_CHECKING:  # the records' TypedDicts exist only in the stubs
    from ._native import Proprioception

#: Reward function: (info before the step, info after it, observation, action) -> reward.
Reward = Callable[[dict[str, Any], dict[str, Any], dict[str, np.ndarray], np.ndarray], float]

#: Bound of the velocity observation, rad/s: the MX register's 1023 units of 0.229 rpm is 24.5
#: rad/s; twice that leaves room.
VELOCITY_BOUND = 50.0
#: Bound of the load register (a signed 16-bit register).
LOAD_BOUND = 32768.0
#: Bound of a strain reading, microstrain: a strain of 1 (a segment stretched to twice its
#: length), far beyond any intact segment (Drosophibot II standing: about 470 at the most).
STRAIN_BOUND = 1e6
#: Bound of the strain sample's age, s: samples come every 24 ms; a second leaves room.
STRAIN_AGE_BOUND_S = 1.0


def forward_progress(before: dict[str, Any], after: dict[str, Any], *_: object) -> float:
    """The thorax's advance along world x in the step, m (0 without a body)."""
    if "body" not in before or "body" not in after:
        return 0.0
    return float(after["body"]["thorax_position_m"][0] - before["body"]["thorax_position_m"][0])


def tilt_rad(orientation: np.ndarray) -> float:
    """Angle between the thorax's z axis and the world's, rad (quaternion w, x, y, z)."""
    # As Python floats: the same doubles, without NumPy's per-scalar overhead on every step.
    _, x, y, _ = np.asarray(orientation, dtype=np.float64).tolist()
    return math.acos(max(-1.0, min(1.0, 1.0 - 2.0 * (x * x + y * y))))


class DbotEnv(gym.Env):
    """Drosophibot II with its firmware: 22 joint targets in, what the board streams out."""

    metadata = {"render_modes": ["rgb_array"], "render_fps": 100}

    def __init__(
        self,
        port: str = "physics",
        *,
        model: Model | None = None,
        gait: Plan | None = None,
        cycles_per_step: int = 1,
        max_episode_steps: int = 1000,
        stiffness_nm_rad: float | None = None,
        settle_s: float = 0.5,
        timeout_cycles: int = 50,
        reply_timeout_s: float = 20.0,
        fall_height_fraction: float = 0.5,
        fall_tilt_rad: float = math.radians(30.0),
        reward: Reward = forward_progress,
        torques: bool = False,
        render_mode: str | None = None,
    ) -> None:
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode {render_mode!r}: give None or 'rgb_array'")
        self.render_mode = render_mode
        self.metadata = {**self.metadata, "render_fps": 100 / cycles_per_step}
        if cycles_per_step < 1:
            raise ValueError(f"cycles_per_step = {cycles_per_step}: give 1 or more")
        self.port = port
        self.model = model if model is not None else Model.builtin("drosophibot2")
        self.scene = self._scene_of(port)
        if self.scene is not None and "+model:" in self.scene:
            # The body's model file is read when the robot opens (at reset); a file that cannot
            # be read or is not a valid model is refused now, named, not at the first reset.
            file = self.scene.split("+model:", 1)[1]
            try:
                Model.load(file)
            except ValueError as e:
                raise ValueError(f"port {port}: model file {file}: {e}") from None
        # The table only tells the board its joint map, calibration, limits and stiffness.
        base = gait if gait is not None else plan(self.model, slices=20)
        self._table = base.step_table()
        #: The gauges the observation carries (``strain_microstrain``'s order); empty on a board.
        self.strain_names: list[str] = list(base.gauge_names) if self.physics else []
        self.gait = gait
        # The plan's prediction [slice, gauge], solved once (``Plan.strain`` solves on access).
        self._predicted = (
            np.asarray(gait.strain, dtype=np.float64)
            if gait is not None and len(gait.gauge_names) > 0
            else None
        )
        self._t0 = 0.0
        self.cycles_per_step = cycles_per_step
        self.max_episode_steps = max_episode_steps
        self.stiffness_nm_rad = stiffness_nm_rad
        self.settle_s = settle_s
        self.timeout_cycles = timeout_cycles
        self.reply_timeout_s = reply_timeout_s
        self.fall_height_fraction = fall_height_fraction
        self.fall_tilt_rad = fall_tilt_rad
        self.reward_fn = reward
        limits = self.model.limits[self.model.servo_joints]
        n = len(self.model.servo_joints)
        self.joint_names = self.model.servo_joint_names
        angles = spaces.Box(limits[:, 0], limits[:, 1], shape=(n,), dtype=np.float64)
        self.torques = torques
        self.stall_nm = np.asarray(self.model.servo_stall_torques_nm, dtype=np.float64)
        self.action_space: spaces.Space = (
            spaces.Dict(
                {
                    "angles_rad": angles,
                    "torques_nm": spaces.Box(-self.stall_nm, self.stall_nm, dtype=np.float64),
                }
            )
            if torques
            else angles
        )
        self._angles_space = angles
        angle = spaces.Box(-2 * np.pi, 2 * np.pi, shape=(n,), dtype=np.float64)
        observed: dict[str, spaces.Space] = {
            "present_rad": angle,
            "velocity_rad_s": spaces.Box(
                -VELOCITY_BOUND, VELOCITY_BOUND, shape=(n,), dtype=np.float64
            ),
            "load_raw": spaces.Box(-LOAD_BOUND, LOAD_BOUND, shape=(n,), dtype=np.float64),
            "setpoint_age": spaces.Box(0.0, 65535.0, shape=(1,), dtype=np.float64),
        }
        if self.strain_names:
            g = len(self.strain_names)
            observed["strain_microstrain"] = spaces.Box(
                -STRAIN_BOUND, STRAIN_BOUND, shape=(g,), dtype=np.float64
            )
            observed["strain_age_s"] = spaces.Box(
                0.0, STRAIN_AGE_BOUND_S, shape=(1,), dtype=np.float64
            )
        self.observation_space = spaces.Dict(observed)
        self.board: Board | None = None
        # The physics robot's step in one native call, made at reset (None: `_step_general`).
        self._fast: EnvStepper | None = None
        # The thorax's world x after the last step, m (the default reward's previous value).
        self._x = 0.0
        self._last_record: Mapping[str, Any] | None = None
        self._steps = 0
        self._info: dict[str, Any] = {}
        self._start_height = 0.0
        self._poses: list[dict[str, Any]] = []
        self._camera: list[float] | None = None

    @staticmethod
    def _scene_of(port: str) -> str | None:
        if port == "physics" or port.startswith("physics+"):
            return "flat" + port[len("physics") :]
        if port.startswith("physics:"):
            return port.split(":", 1)[1]
        return None

    @property
    def physics(self) -> bool:
        """Whether the environment runs on the physics robot."""
        return self.scene is not None

    @property
    def has_strain(self) -> bool:
        """Whether the observation carries the strain gauges (``strain_microstrain``,
        ``strain_age_s``): on the physics robot with a model that has gauges; not on a board."""
        return bool(self.strain_names)

    # -- reset -------------------------------------------------------------------------------

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        """The robot standing in its resting posture, streaming. Options: ``scene`` (physics
        robot only: ``flat``, ``incline:DEG``, ``ball``, ``ball-fixed``) and ``stiffness_nm_rad``
        (every servo's stiffness, N m/rad: P gain and torque bias; None: the model's)."""
        super().reset(seed=seed)
        self._fast = None
        board = self._prepare_board(options, [(0, self._table)])
        board.enter_streaming(timeout_cycles=self.timeout_cycles, feedback_every=1)
        first = self._next(board)
        if first is None:
            raise RuntimeError(f"{self.port}: no proprioception after entering streaming")
        # The resting posture is what the firmware holds: the first setpoint keeps it.
        self.rest_rad = np.asarray(first["commanded_rad"][0], dtype=np.float64)
        self._steps = 0
        got = self._cycles(self.rest_rad, 1)
        if got is None:
            raise RuntimeError(f"{self.port}: streaming stopped at once: {board.status()}")
        obs, time_s = got
        self._t0 = time_s
        episode = self._begin_episode(obs, self._make_info(time_s))
        if self.physics:
            self._x = float(self._info["body"]["thorax_position_m"][0])
            self._fast = EnvStepper(
                board,
                self._angles_space.low,
                self._angles_space.high,
                self.stall_nm,
                self.cycles_per_step,
                1.0,
                self.has_strain,
                self.fall_height_fraction * self._start_height,
                self.fall_tilt_rad,
            )
        return episode

    def _prepare_board(self, options: dict[str, Any] | None, uploads: list) -> Board:
        """A fresh board with each ``(slot, table)`` of ``uploads`` uploaded, the reset
        ``options`` applied (``scene``, ``stiffness_nm_rad``; any other is refused by name),
        torque on and the robot settled standing."""
        options = dict(options or {})
        if "scene" in options:
            if not self.physics:
                raise ValueError(f"scene: the port {self.port} is a board, not the physics robot")
            self.scene = str(options.pop("scene"))
        stiffness = options.pop("stiffness_nm_rad", self.stiffness_nm_rad)
        if options:
            raise ValueError(f"unknown reset options: {', '.join(sorted(options))}")
        board = self._fresh_board()
        for slot, table in uploads:
            board.upload(slot, table)
            self._clear_upload_fault(board)
        if stiffness is not None:
            for j in range(len(self.joint_names)):
                board.set_stiffness(j, float(stiffness))
        board.set_torque(True)
        # The physics robot's gravity ramps in over 1 s from torque-on; then it settles.
        board.wait((1.0 if self.physics else 0.0) + self.settle_s)
        state = board.status()["state"]
        if state != "Standing":
            raise RuntimeError(f"{self.port}: not standing after torque on (state {state})")
        return board

    def _begin_episode(
        self, obs: dict[str, np.ndarray], info: dict[str, Any]
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        """The episode's first observation and info: the start height (the fall rule's), the
        camera and the first rendered pose are taken from them."""
        self._info = info
        if self.physics:
            self._start_height = float(info["body"]["thorax_position_m"][2])
        self._poses = []
        self._camera = None
        if self.render_mode is not None:
            self._poses.append(self._pose(obs))
            self._camera = list(camera_half_extent(self.model, self._poses[0], self._scene_text()))
        return obs, dict(info)

    def _fresh_board(self) -> Board:
        if self.physics:
            if self.board is not None:
                self.board.close()
            self.board = Board.open(f"physics:{self.scene}", reply_timeout_s=self.reply_timeout_s)
            return self.board
        if self.board is None:
            self.board = Board.open(self.port, reply_timeout_s=self.reply_timeout_s)
        board = self.board
        state = board.status()["state"]
        if state == "Fault":
            board.clear_fault()
        elif state in ("Streaming", "Walking", "Ramping", "Stopping"):
            board.stop()
            self._wait_stopped(board)
        if board.status()["state"] == "Standing":
            board.set_torque(False)
        return board

    def _wait_stopped(self, board: Board) -> None:
        """Waits (up to 30 s of polling) for a stopped walk to stand or idle."""
        for _ in range(3000):
            if board.status()["state"] in ("Standing", "Idle"):
                break
            board.wait(0.01)

    @staticmethod
    def _wait_cycles(board: Board, cycles: int) -> None:
        """Lets `cycles` bus cycles pass, counted on the board's own cycle counter (a port's clock
        is wall time, and the emulator runs slower than real time)."""
        target = board.status()["counters"]["cycles"] + cycles
        for _ in range(100 * cycles):
            if board.status()["counters"]["cycles"] >= target:
                return
            board.wait(0.01)
        raise RuntimeError(f"{board.port}: {cycles} bus cycles did not pass")

    def _clear_upload_fault(self, board: Board) -> None:
        # The emulated board may report ServoMissing while its flash is written (bus cycles
        # stall; see python/tests/conftest.py `upload`): that fault is cleared here. A table with
        # new servo IDs sends the board back to Boot while it finds them.
        self._wait_cycles(board, 30)
        if board.status()["state"] == "Fault":
            board.clear_fault()
            self._wait_cycles(board, 30)
        for _ in range(1000):
            if board.status()["state"] in ("Idle", "Standing"):
                return
            self._wait_cycles(board, 1)
        raise RuntimeError(f"{self.port}: not idle after the upload: {board.status()}")

    # -- step --------------------------------------------------------------------------------

    def step(
        self, action: Any
    ) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        fast = self._fast
        if fast is None or self.reward_fn is not forward_progress:
            return self._step_general(action)
        # The physics robot with the default reward: clip, exchange, observation, info and the
        # fall rule in one call (`EnvStepper`, python/src/env_step.rs); the same values as
        # `_step_general` (python/tests/test_env_fast_step.py).
        if self.torques:
            got = fast.step(action["angles_rad"], action["torques_nm"])
        else:
            got = fast.step(action)
        self._steps += 1
        truncated = self._steps >= self.max_episode_steps
        self._last_record = None
        if got is None:
            return self._stopped(truncated)
        obs, info, x, fell = got
        reward = x - self._x
        self._x = x
        self._last_obs = obs
        if self._predicted is not None:
            self._add_plan(info)
        self._info = info
        if self.render_mode is not None:
            self._poses.append(self._pose(obs))
        return obs, reward, fell, truncated, dict(info)

    def _step_general(
        self, action: Any
    ) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        """`step` on any port with any reward: each part in Python, over `Board.stream_step`."""
        if self.board is None:
            raise RuntimeError("call reset() before step()")
        target, torque = self._split(action)
        before = self._info
        got = self._cycles(target, self.cycles_per_step, torque)
        self._steps += 1
        truncated = self._steps >= self.max_episode_steps
        if got is None:
            return self._stopped(truncated)
        obs, time_s = got
        info = self._make_info(time_s)
        self._info = info
        if self.physics:
            self._x = float(info["body"]["thorax_position_m"][0])
        if self.render_mode is not None:
            self._poses.append(self._pose(obs))
        terminated = info["state"] == "Fault" or self._fell(info)
        reward = float(self.reward_fn(before, info, obs, target))
        return obs, reward, terminated, truncated, dict(info)

    def _stopped(
        self, truncated: bool
    ) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        """The step's return when streaming stopped: the firmware went safe (or the link broke).
        The last observation stays; reward 0, terminated."""
        assert self.board is not None
        info = {"state": self.board.status()["state"], "time_s": self._info.get("time_s", 0.0)}
        if self.physics:
            info["body"] = self.board.body()
            self._x = float(info["body"]["thorax_position_m"][0])
        self._info = info
        return self._last_obs, 0.0, True, truncated, dict(info)

    def _next(self, board: Board) -> Proprioception | None:
        timeout = 1.0 if self.physics else self.reply_timeout_s
        return board.next_proprioception(timeout_s=timeout)

    def _split(self, action: Any) -> tuple[np.ndarray, np.ndarray | None]:
        """The clipped joint targets and, with ``torques=True``, the clipped torques."""
        # np.clip's own rule, minimum(maximum(x, low), high) (a NaN stays NaN), without its
        # dispatch layers.
        low, high = self._angles_space.low, self._angles_space.high
        if not self.torques:
            return np.minimum(np.maximum(np.asarray(action, dtype=np.float64), low), high), None
        angles = np.asarray(action["angles_rad"], dtype=np.float64)
        angles = np.minimum(np.maximum(angles, low), high)
        torques = np.minimum(
            np.maximum(np.asarray(action["torques_nm"], dtype=np.float64), -self.stall_nm),
            self.stall_nm,
        )
        return angles, torques

    def _cycles(
        self, target: np.ndarray, n: int, torque: np.ndarray | None = None
    ) -> tuple[dict[str, np.ndarray], float] | None:
        """The setpoint sent for each of `n` bus cycles: the last cycle's observation and its
        time (s), None if streaming stopped (`Board.stream_step`, one call)."""
        assert self.board is not None
        timeout = 1.0 if self.physics else self.reply_timeout_s
        got = self.board.stream_step(target, torque, cycles=n, timeout_s=timeout)
        self._last_record = None
        if got is None:
            return None
        obs, time_s = got
        if not self.strain_names:
            obs.pop("strain_microstrain", None)
            obs.pop("strain_age_s", None)
        self._last_obs = obs
        return obs, time_s

    @property
    def last_record(self) -> Mapping[str, Any] | None:
        """The last step's proprioception record whole (a dict of arrays with one row, as
        ``Board.next_proprioception`` gives it), built when asked."""
        if self._last_record is None and self.board is not None:
            self._last_record = self.board.last_stream_record()
        return self._last_record

    @last_record.setter
    def last_record(self, rec: Mapping[str, Any] | None) -> None:
        self._last_record = rec

    @staticmethod
    def _joints_observed(rec: Mapping[str, Any], setpoint_age: np.ndarray) -> dict[str, np.ndarray]:
        """The observation's joint keys from the one row of a record (proprioception or
        telemetry), with ``setpoint_age``."""
        return {
            "present_rad": np.asarray(rec["present_rad"][0], dtype=np.float64),
            "velocity_rad_s": np.asarray(rec["velocity_rad_s"][0], dtype=np.float64),
            "load_raw": np.asarray(rec["load_raw"][0], dtype=np.float64),
            "setpoint_age": setpoint_age,
        }

    def _make_info(self, time_s: float) -> dict[str, Any]:
        assert self.board is not None
        info: dict[str, Any] = {"time_s": time_s, "state": "Streaming"}
        if self.physics:
            info["body"] = self.board.body()
        if self._predicted is not None:
            self._add_plan(info)
        return info

    def _add_plan(self, info: dict[str, Any]) -> None:
        """``plan_phase`` and ``predicted_strain_microstrain`` at ``info["time_s"]``."""
        phase = self.plan_phase(info["time_s"])
        info["plan_phase"] = phase
        info["predicted_strain_microstrain"] = self.predicted_strain(phase)

    def plan_phase(self, time_s: float) -> float:
        """The plan's phase at ``time_s`` (the proprioception clock): the time since reset over
        the plan's period, modulo 1. Needs ``gait=``."""
        if self.gait is None:
            raise RuntimeError("plan_phase needs the plan: give DbotEnv(gait=...)")
        return float(((time_s - self._t0) / self.gait.period_s) % 1.0)

    def predicted_strain(self, phase: float) -> np.ndarray:
        """The plan's predicted strain at ``phase`` (fraction of the period), microstrain per
        gauge: linear between the slices (slice ``s`` at phase ``s / slices``)."""
        if self._predicted is None:
            raise RuntimeError("predicted_strain needs a plan with gauges: give DbotEnv(gait=...)")
        n = self._predicted.shape[0]
        s = (phase % 1.0) * n
        s0 = int(math.floor(s)) % n
        w = s - math.floor(s)
        return (1.0 - w) * self._predicted[s0] + w * self._predicted[(s0 + 1) % n]

    def _fell(self, info: dict[str, Any]) -> bool:
        if "body" not in info:
            return False
        body = info["body"]
        low = body["thorax_position_m"][2] < self.fall_height_fraction * self._start_height
        return bool(low or tilt_rad(body["thorax_orientation"]) > self.fall_tilt_rad)

    # -- rendering ---------------------------------------------------------------------------

    def _scene_text(self) -> str:
        return self.scene if self.scene is not None else "flat"

    def _pose(self, obs: dict[str, np.ndarray]) -> dict[str, Any]:
        """The present pose for the drawing: the body's thorax and foot contacts on the physics
        robot; upright at the origin, every foot down, on a board."""
        q = np.zeros(len(self.model.joint_names))
        q[self.model.servo_joints] = obs["present_rad"]
        body = self._info.get("body")
        if body is not None:
            position = np.asarray(body["thorax_position_m"], dtype=np.float64)
            orientation = np.asarray(body["thorax_orientation"], dtype=np.float64)
            stance = [bool(c) for c in body["foot_contact"]]
        else:
            position = np.array([0.0, 0.0, 0.0])
            orientation = np.array([1.0, 0.0, 0.0, 0.0])
            stance = [True] * len(self.model.legs)
        t = float(self._info.get("time_s", 0.0))
        return {
            "thorax_position_m": position,
            "thorax_orientation": orientation,
            "q": q,
            "stance": stance,
            "caption": f"{self.port} on {self._scene_text()}: t = {t:.2f} s, step {self._steps}",
        }

    def render(self) -> np.ndarray | None:
        """The present pose as an RGB array (420, 1200, 3), or None without ``render_mode``."""
        if self.render_mode is None:
            return None
        if not self._poses or self._camera is None:
            raise RuntimeError("call reset() before render()")
        return render_pose(self.model, self._poses[-1], self._camera, self._scene_text())

    def write_gif(self, path: str, every: int = 1) -> int:
        """Writes the episode so far (every ``every``-th step) as a GIF at ``path``, the camera
        following the thorax, one frame per drawn step at the simulated pace; returns the frame
        count. Needs ``render_mode="rgb_array"`` (the poses are kept only then)."""
        if self.render_mode is None:
            raise RuntimeError("write_gif needs render_mode='rgb_array'")
        poses = self._poses[:: max(1, every)]
        delay_ms = round(10 * self.cycles_per_step * max(1, every))
        return write_walk_gif(self.model, poses, path, self._scene_text(), delay_ms)

    def close(self) -> None:
        self._fast = None
        if self.board is not None:
            try:
                if not self.physics and self.board.status()["state"] == "Streaming":
                    self.board.leave_streaming()
            finally:
                self.board.close()
                self.board = None


# N physics robots at once, stepped on Rust threads (python/dbot/vector_env.py), and the ids that
# `gymnasium.make` / `gymnasium.make_vec` know: ``gymnasium.make_vec("dbot/Physics-v0",
# num_envs=N)`` builds a :class:`VectorEnv`, ``gymnasium.make("dbot/Physics-v0")`` a
# :class:`DbotEnv` on the physics robot.
from .vector_env import ENV_ID, VectorEnv  # noqa: E402

if ENV_ID not in gym.registry:
    gym.register(
        id=ENV_ID,
        entry_point="dbot.env:DbotEnv",
        vector_entry_point="dbot.vector_env:VectorEnv",
    )

"""Type stubs of the native module ``dbot._native`` (PyO3). See the package docstring."""

from os import PathLike
from typing import Any, Literal, TypedDict

import numpy as np
import numpy.typing as npt

__version__: str
BUILTIN_MODELS: list[str]

class DbotError(Exception):
    """Base class of the errors raised by dbot."""

class BoardError(DbotError):
    """The link to a board failed: it vanished, did not answer, or refused a request."""

class Model:
    """An organism model: bodies, joints, feet and the servo map."""

    @staticmethod
    def builtin(name: str) -> Model:
        """A built-in model by name (``BUILTIN_MODELS``); ValueError naming the known ones."""
    @staticmethod
    def load(path: str | PathLike[str]) -> Model:
        """A model from a ``.toml`` model file or an AnimatLab ``.aproj`` project."""
    @property
    def name(self) -> str: ...
    @property
    def joint_names(self) -> list[str]:
        """Every joint's full name (``LF_ThC1``, ...), model order: the columns of ``Plan.angles``."""
    @property
    def servo_joint_names(self) -> list[str]:
        """Joints with a servo, in the board's joint-map order: the columns of setpoints,
        telemetry and proprioception."""
    @property
    def servo_joints(self) -> list[int]:
        """Indices into ``joint_names`` of the servo joints."""
    @property
    def legs(self) -> list[str]: ...
    @property
    def limits(self) -> npt.NDArray[np.float64]:
        """Joint limits, rad: [joint, 2] of (lower, upper)."""
    @property
    def mass_kg(self) -> float: ...

class Plan:
    """A planned step cycle; arrays are indexed [slice, joint] / [slice, leg]."""

    @property
    def angles(self) -> npt.NDArray[np.float64]:
        """Joint angles, rad: [slice, joint] in ``joint_names`` order."""
    @property
    def velocities(self) -> npt.NDArray[np.float64]:
        """rad/s: [slice, joint]."""
    @property
    def accelerations(self) -> npt.NDArray[np.float64]:
        """rad/s^2: [slice, joint]."""
    @property
    def stance(self) -> npt.NDArray[np.bool_]:
        """[slice, leg] in ``legs`` order."""
    @property
    def feet(self) -> npt.NDArray[np.float64]:
        """Foot targets in the thorax frame, m: [slice, leg, xyz]."""
    @property
    def torques(self) -> npt.NDArray[np.float64]:
        """Actuator torques of the inverse dynamics (floating base), N m: [slice, joint]."""
    @property
    def legs(self) -> list[str]: ...
    @property
    def joint_names(self) -> list[str]: ...
    @property
    def phases(self) -> list[float]:
        """Start of each leg's cycle, fraction of the period."""
    @property
    def dt(self) -> float:
        """Slice duration, s."""
    @property
    def period_s(self) -> float: ...
    @property
    def duty(self) -> float: ...
    @property
    def slices(self) -> int: ...
    @property
    def model(self) -> Model: ...
    def step_table(self, name: str = "dbot-gait", torques: bool = False) -> bytes:
        """The board's step table; with ``torques`` the planned torques are the bias feed-forward."""

def plan(
    model: Model,
    *,
    preset: str | None = None,
    swing_s: float = ...,
    duty: float = ...,
    step_height_m: dict[str, float] = ...,
    translation_m: float = ...,
    rotation_rad: float = ...,
    body_height_m: dict[str, float] = ...,
    gait: dict[str, float] = ...,
    slices: int = ...,
    terrain: str = ...,
    ball_radius_m: float = ...,
    ball_offset_m: float = ...,
    placement: dict[str, dict[str, float]] = ...,
) -> Plan:
    """Plans one step cycle from ``preset``'s stepping parameters, as ``dbot plan --preset`` does
    (``None``: the CLI's default, ``servo-safe``, table 1 at a swing the servos can follow - 1.0 s on
    Drosophibot II; ``table1`` has the original solver's 0.5 s; also ``physical-robot``,
    ``paper-comparison``); keyword arguments override the preset's values
    (``step_height_m``/``body_height_m``: {hind, middle, front}; ``gait``: {phi_i, phi_c};
    ``placement``: {forward_m: {..}, outward_m: {..}})."""

class PlanDir:
    """A plan directory written by ``dbot plan`` or ``dbot demo``; arrays are indexed [slice, joint] /
    [slice, leg]."""

    @property
    def angles(self) -> npt.NDArray[np.float64]:
        """Joint angles, rad: [slice, joint] in ``joint_names`` order."""
    @property
    def torques(self) -> npt.NDArray[np.float64] | None:
        """Actuator torques, N m: [slice, joint]; None when planned without dynamics."""
    @property
    def stance(self) -> npt.NDArray[np.bool_]:
        """[slice, leg] in ``legs`` order."""
    @property
    def legs(self) -> list[str]: ...
    @property
    def joint_names(self) -> list[str]: ...
    @property
    def period_s(self) -> float: ...
    @property
    def duty(self) -> float: ...
    @property
    def slices(self) -> int: ...
    @property
    def format_version(self) -> int:
        """The plan directory format version (plan.json's ``format_version``)."""
    @property
    def table_name(self) -> str:
        """The gait name its step table gets by default."""
    @property
    def model(self) -> Model: ...
    def step_table(self, name: str | None = None) -> bytes:
        """The board's step table: the bytes ``dbot table --plan DIR`` writes."""

def read_plan_dir(path: str | PathLike[str]) -> PlanDir:
    """Reads a plan directory; ValueError naming the file, line or format version."""

class Fault(TypedDict):
    kind: str
    """The fault with its numbers, e.g. ``ServoStuck { goal_range: 312, present_range: 0 }``."""
    name: Literal[
        "EmergencyStop", "ServoError", "ServoMissing", "SetpointTimeout", "Watchdog", "ServoStuck"
    ]
    joint: int | None
    message: str

class Counters(TypedDict):
    """The board's counters since boot (they wrap at 2**32)."""

    cycles: int
    """Bus cycles performed, whatever the state: the board's own clock."""
    missed_deadlines: int
    """Cycle starts missed because the previous cycle ran past its slot."""
    bus_timeouts: int
    """Servo replies that did not come in time."""
    crc_errors: int
    """Servo replies that failed their CRC."""
    rejected_frames: int
    """Frames from the host that could not be decoded."""
    telemetry_dropped: int
    """Telemetry / proprioception records dropped because the host did not read them in time."""

class Status(TypedDict):
    state: Literal["Idle", "Standing", "Ramping", "Walking", "Stopping", "Streaming", "Fault"]
    fault: Fault | None
    torque_enabled: int
    counters: Counters
    playback: tuple[int, int, int] | None

class Records(TypedDict):
    """Per-cycle records: [record] and [record, joint] arrays (joint-map order)."""

    time_s: npt.NDArray[np.float64]
    cycle: npt.NDArray[np.int64]
    cycle_us: npt.NDArray[np.int64]
    commanded_rad: npt.NDArray[np.float64]
    present_rad: npt.NDArray[np.float64]
    velocity_rad_s: npt.NDArray[np.float64]
    load_raw: npt.NDArray[np.int32]
    """Register 126 as read: MX-28 load in 0.1 % of max, MX-64 current in ~3.36 mA."""
    error: npt.NDArray[np.int32]
    flags: npt.NDArray[np.int32]
    joint_names: list[str]
    """Name of each joint column (``LF_ThC1``, ...), as ``Board.joint_names``."""

class Telemetry(Records):
    step: npt.NDArray[np.int64]
    slice: npt.NDArray[np.int64]

class Proprioception(Records):
    time_us: npt.NDArray[np.int64]
    setpoint_seq: npt.NDArray[np.int64]
    setpoint_age: npt.NDArray[np.int64]

class Board:
    """A board, the RP2040 emulator's pseudo-terminal, or the in-process virtual robot."""

    @staticmethod
    def open(port: str, reply_timeout_s: float = 2.0) -> Board:
        """``/dev/ttyACM0`` or a pty path, ``virtual``, ``virtual:PATH``, ``physics`` or ``physics:SCENE``; checks versions."""
    @property
    def port(self) -> str: ...
    @property
    def joint_names(self) -> list[str]:
        """The board's joints in joint-map order: the model joint each servo of the gait in use
        drives (if this ``Board`` uploaded it), else the model's servo joints; ``J<n>`` otherwise."""
    def set_model(self, model: Model) -> None:
        """The model whose joint names label records (default: the built-in drosophibot2)."""
    def now(self) -> float:
        """The board's clock as the host sees it, s (simulated time on the virtual robot)."""
    def close(self) -> None:
        """Closes the link (a serial port is exclusive); later calls raise BoardError."""
    def __enter__(self) -> Board: ...
    def __exit__(self, *args: object) -> bool: ...
    def info(self) -> dict[str, Any]: ...
    def status(self) -> Status:
        """State, fault, torque mask, playback position and the counters since boot
        (:class:`Counters`, named integers)."""
    def upload(self, slot: int, table: bytes) -> int:
        """Uploads and verifies a step table; returns the bytes sent."""
    def upload_plan(
        self, slot: int, plan: Plan, name: str = "dbot-gait", torques: bool = False
    ) -> int: ...
    def play(
        self,
        slot: int,
        steps: int | None = None,
        period_scale: float = 1.0,
        backward: bool = False,
    ) -> None: ...
    def stop(self) -> None: ...
    def emergency_stop(self) -> None: ...
    def clear_fault(self) -> None: ...
    def set_torque(self, enable: bool, joint: int | None = None) -> None: ...
    def set_telemetry(self, every: int) -> None:
        """Telemetry every ``every`` bus cycles (0: off) outside streaming; streaming's
        proprioception follows ``enter_streaming(feedback_every=...)`` instead."""
    def set_bus(self, baud: int, cycle_hz: int) -> None: ...
    def wait(self, seconds: float) -> None:
        """Lets time pass on the board's clock, keeping telemetry and proprioception."""
    def record(self, duration_s: float) -> Telemetry: ...
    def enter_streaming(self, timeout_cycles: int = 5, feedback_every: int = 1) -> None:
        """From standing only. No setpoint for ``timeout_cycles`` cycles: hold, then safe
        (state ``Fault``, fault kind ``SetpointTimeout``). Proprioception every
        ``feedback_every`` cycles (1: every cycle) whatever ``set_telemetry`` says; each record's
        ``setpoint_seq``, ``setpoint_age`` and ``commanded_rad`` are what its cycle wrote to the
        servos (``setpoint_seq`` 0: no setpoint yet this session)."""
    def leave_streaming(self) -> None: ...
    def send_setpoint(
        self,
        angles_rad: npt.ArrayLike,
        torques_nm: npt.ArrayLike | None = None,
    ) -> int:
        """Targets for the next bus cycle (rad, joint-map order); returns the sequence number."""
    def next_proprioception(self, timeout_s: float = 0.1) -> Proprioception | None: ...
    def drain_proprioception(self) -> Proprioception: ...

class PhysicsWalk:
    """A recorded walk of a plan directory's gait on the physics robot (:func:`physics_walk`)."""
    @property
    def steps(self) -> int: ...
    @property
    def cycles(self) -> int:
        """Bus cycles recorded."""
    @property
    def duration_s(self) -> float:
        """Simulated seconds recorded."""

def physics_walk(
    plan_dir: str | PathLike[str],
    steps: int,
    out: str | PathLike[str],
    backward: bool = False,
    scene: str = "flat",
) -> PhysicsWalk:
    """Walks the gait of ``plan_dir`` (written by ``dbot plan`` / ``dbot demo``; its step table is
    ``dbot table --plan``'s) for ``steps`` steps on a fresh physics robot on ``scene``, recording
    into ``out`` (telemetry.csv, torque.png, angles.png). ValueError naming the file or the count."""

class LegTrackingFigures(TypedDict):
    rms_rad: float
    max_abs_rad: float
    joints: int

class LoadFit(TypedDict):
    r2: float | None
    """R^2 of the planned torque predicting the load (1 - SS_res / SS_tot; None: no variation)."""
    rms_nm: float
    samples: int

class WalkFigures(TypedDict):
    distance_per_step_m: float
    planned_per_step_m: float
    distance_off_percent: float
    stroke_m: float
    lateral_m: float
    heading_rad: float
    height_start_m: float
    height_min_m: float
    height_end_m: float
    tilt_max_rad: float
    slip_m: dict[str, float]
    """Horizontal distance each foot moved while loaded, by leg name."""
    tracking: dict[str, LegTrackingFigures]
    """Present - planned angle per leg over the steps after the first (empty with one step)."""
    loads: dict[str, LoadFit]
    """Servo load (ESTIMATE from Present Load) against the planned torque, by joint name, over the
    whole steps after the first."""

def walk_figures(walk: PhysicsWalk) -> WalkFigures:
    """The figures ``dbot demo`` prints for a walk, from what it recorded (SI units)."""

"""Type stubs of the native module ``dbot._native`` (PyO3). See the package docstring."""

from os import PathLike
from typing import Any, Literal, NotRequired, TypedDict, final

import numpy as np
import numpy.typing as npt

__version__: str
BUILTIN_MODELS: list[str]

class DbotError(Exception):
    """Base class of the errors raised by dbot."""

class BoardError(DbotError):
    """The link to a board failed: it vanished, did not answer, or refused a request."""

class TrialFaulted(DbotError):
    """The board stopped the robot on a fault during ``Board.record_trial`` (a servo missing,
    stuck or overloaded, a setpoint timeout, an emergency stop): the trial is kept with outcome
    ``"faulted"`` (trial.json's ``fault`` names the fault, joint and bus cycle), and the message
    names the trial folder."""

@final
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
    def servo_stall_torques_nm(self) -> list[float]:
        """Stall torque of each servo joint's actuator, N m (``servo_joint_names`` order)."""
    def load_torques_nm(self, load_raw: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """Servo torques from register 126 values (``load_raw``, any shape, last axis the servo
        joints), N m, an ESTIMATE as ``dbot record``'s ``torque_estimate_nm``: MX-28 Present Load
        (0.1 % of maximum) x stall torque; MX-64 Present Current (3.36 mA/unit) x stall torque /
        stall current. The register's sign (servo direction); NaN without a servo. ValueError
        naming the joint of a value that is not a register value, or a wrong last axis."""
    @property
    def legs(self) -> list[str]: ...
    @property
    def limits(self) -> npt.NDArray[np.float64]:
        """Joint limits, rad: [joint, 2] of (lower, upper)."""
    @property
    def mass_kg(self) -> float: ...

@final
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
    def strain(self) -> npt.NDArray[np.float64]:
        """Predicted gauge strain from the inverse dynamics (floating base), microstrain:
        [slice, gauge] in ``gauge_names`` order (docs/strain.md)."""
    @property
    def gauge_names(self) -> list[str]:
        """The model's strain gauges, e.g. ``LF_troch_axial`` (Drosophibot II: the strain board's
        channel order)."""
    @property
    def model(self) -> Model: ...
    def step_table(
        self, name: str = "dbot-gait", torques: bool = False, allow_infeasible: bool = False
    ) -> bytes:
        """The board's step table; with ``torques`` the planned torques are the bias feed-forward.

        Built under the rules ``dbot table`` enforces (the same library call): more slices than a
        gait slot holds, a servo that cannot follow the plan (speed over the no-load speed, with
        ``torques`` also torque over stall or the torque-speed line; an inverse-kinematics jump),
        a stiffness the servo's P gain cannot hold, or an angle outside a joint's limits raise
        ValueError with ``dbot``'s words (naming joint, slice and margin). ``allow_infeasible``
        builds an infeasible plan anyway and says what it let through as a UserWarning."""
    def write(
        self, dir: str | PathLike[str], *, name: str | None = None, dynamics: bool = True
    ) -> list[str]:
        """Writes the plan directory ``dbot plan`` writes, by the same library call: plan.json,
        model.toml, model.urdf, joints.csv, feet.csv, the plots, feasibility.md, README.md, and with
        ``dynamics`` (``dbot plan``'s default options) the torque and GRF columns,
        joint_forces.csv, torques.png, grf.png and for a model with gauges strain.csv and
        strain.png. ``dir`` is created if missing; each file is replaced whole. ``name`` is the
        gait name its step table gets (at most 16 bytes; default: the directory's name). Returns
        the names of the files written; ``read_plan_dir(dir)`` reads it back."""

def plan(
    model: Model,
    *,
    preset: str | None = None,
    turn_deg: float | None = None,
    radius_m: float | None = None,
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
    ``placement``: {forward_m: {..}, outward_m: {..}}). ``turn_deg`` (thorax yaw per step, deg,
    positive left) and ``radius_m`` (of the thorax path, m, positive with the centre on the left)
    plan a curve as ``dbot plan --turn --radius`` does: ``turn_deg`` alone keeps the stride,
    ``radius_m`` alone sets the turn from the stride, both set the stride (``radius_m=0``: on the
    spot); out-of-range values raise ``ValueError`` naming the parameter."""

class Standing(TypedDict):
    """The robot standing still on flat ground in the physics robot's resting posture, solved as a
    plan's slice is (:func:`plan_standing`)."""

    angles_rad: npt.NDArray[np.float64]
    """Servo joints (``Model.servo_joint_names`` order), rad: the resting posture."""
    torques_nm: npt.NDArray[np.float64]
    """Servo joints, N m: the actuator torques that hold it (the torque bias's feed-forward)."""
    foot_force_n: npt.NDArray[np.float64]
    """[foot, xyz], N: the solver's ground reaction forces (model foot order)."""
    gauge_names: list[str]
    strain_microstrain: npt.NDArray[np.float64]
    """Predicted reading of each gauge, microstrain (``gauge_names`` order)."""

def plan_standing(model: Model) -> Standing:
    """The planner's solution of ``model`` standing still on flat ground in the posture the
    physics robot starts in: the prediction docs/validation.md's ``strain`` block compares the
    simulated gauges with. ValueError naming the model if it cannot stand or its gauges are bad."""

@final
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
    def step_table(self, name: str | None = None, allow_infeasible: bool = False) -> bytes:
        """The board's step table: the bytes ``dbot table --plan DIR`` writes, refused as it
        refuses (ValueError, the same words); ``allow_infeasible`` is ``--allow-infeasible``
        (its warning as a UserWarning)."""

def read_plan_dir(path: str | PathLike[str]) -> PlanDir:
    """Reads a plan directory; ValueError naming the file, line or format version."""

class Trial(TypedDict):
    """A trial folder written by ``dbot record``, one record per bus cycle."""

    time_s: npt.NDArray[np.float64]
    """[record]: board time since the first record, s."""
    cycle: npt.NDArray[np.int64]
    step: npt.NDArray[np.int64]
    slice: npt.NDArray[np.int64]
    run_state: list[str | None]
    """[record]: the board's run state (``"Walking"``, ``"Fault"``, ...); None in a trial
    written before the column."""
    planned_rad: npt.NDArray[np.float64]
    """[record, joint]: the goal less the torque bias at the stiffness the board held (the goal
    itself at stiffness 0); NaN without a step table."""
    commanded_rad: npt.NDArray[np.float64]
    """[record, joint]; NaN while torque is off (no goal driven)."""
    present_rad: npt.NDArray[np.float64]
    velocity_rad_s: npt.NDArray[np.float64]
    torque_estimate_nm: npt.NDArray[np.float64]
    """[record, joint]: an ESTIMATE from the load register; NaN without a step table."""
    modelled_torque_nm: npt.NDArray[np.float64]
    load_raw: npt.NDArray[np.int32]
    error: npt.NDArray[np.int32]
    flags: npt.NDArray[np.int32]
    joint_names: list[str]
    meta: dict[str, Any]
    """trial.json: format_version, folder, outcome (complete, interrupted, failed, faulted),
    fault (kind, reason, joint, joint_name, cycle; None unless faulted), started, host_version, command_line, port,
    firmware, settings, gait, plan, direction, period_scale, steps, substrate, strain,
    perturbation (leg, step, rest, moved_to, platform_id), notes, joints, cycles, duration_s, missing_records (skipped cycle numbers),
    lost_records (of those, dropped on the board or the host; None if not known)."""
    path: str

def read_trial(path: str | PathLike[str]) -> Trial:
    """Reads a trial folder; ValueError naming the file and line (or format version)."""

class ComparisonRow(TypedDict):
    leg: str
    dof: str
    #: ``"A"`` or ``"B"``: the side whose joints were summed (ThC2+CTr); ``""`` for a plain DoF.
    summed_in: str
    r2_angle: float | None
    r2_torque: float | None

def compare(
    a: str | PathLike[str], b: str | PathLike[str], out: str | PathLike[str]
) -> list[ComparisonRow]:
    """Per common DoF of ``a`` and ``b`` (plan directories or trial folders, in any mix) the R^2 of
    a linear regression of the angles and of the torques, as ``dbot compare A B``; writes
    compare.csv and the overlay plots into ``out``. A trial's traces are its measured angles and
    estimated torques averaged per slice over steps 1 to the last whole one."""

class DoctorItem(TypedDict):
    name: str
    outcome: Literal["pass", "fail", "not checked"]
    detail: str
    fix: str | None

class DoctorReport(TypedDict):
    ok: bool
    items: list[DoctorItem]
    text: str

def doctor(
    port: str | None = None,
    bus: str | None = None,
    baud: int | None = None,
    strain: str | None = None,
    strain_seconds: float = 2.0,
    model: Model | None = None,
    quiet: bool = False,
) -> DoctorReport:
    """The bring-up check of ``dbot doctor``, same items and words: the board on ``port``, every
    servo of ``model`` on the servo bus (``bus``, or the virtual/physics robot's own), the supply
    voltage from the servos, the strain board on ``strain``. Prints the items unless ``quiet``;
    ``ok`` is False when any item failed."""

FaultKey = Literal[
    "EmergencyStop", "ServoError", "ServoMissing", "SetpointTimeout", "Watchdog", "ServoStuck"
]

class Fault(TypedDict):
    kind: FaultKey
    """The fault's key, e.g. ``ServoStuck`` (the same as ``name``)."""
    name: FaultKey
    detail: str
    """What the fault is, in words with its numbers, e.g. ``servo stuck: its goal moved over 312
    ticks, its position over 0``."""
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
    rate_limited: int
    """Goal moves the board cut to what the servo can move in one bus cycle (a streamed setpoint
    further away, or the torque bias after a stiffness change while walking)."""

class Status(TypedDict):
    state: Literal["Idle", "Standing", "Ramping", "Walking", "Stopping", "Streaming", "Fault", "Boot"]
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
    platform_goal_ticks: NotRequired[npt.NDArray[np.float64]]
    """[record]: a platform set up only: its servo's goal, ticks (NaN: a record without it)."""
    platform_present_ticks: NotRequired[npt.NDArray[np.float64]]
    """[record]: a platform set up only: its servo's present position, ticks (NaN: none)."""
    run_state: list[str]
    """[record]: the board's run state (``"Walking"``, ..., ``"Fault"`` from the first cycle
    after a fault stopped the robot)."""

class Proprioception(Records):
    time_us: npt.NDArray[np.int64]
    setpoint_seq: npt.NDArray[np.int64]
    setpoint_age: npt.NDArray[np.int64]
    strain_names: NotRequired[list[str]]
    """Physics robot, or a strain board attached (``Board.attach_strain``): the gauges (the
    strain board's names)."""
    strain_microstrain: NotRequired[npt.NDArray[np.float64]]
    """[record, gauge]: physics: the latest simulated sample at or before each record; attached
    board: (counts - baseline) / gain of the latest sample when the host read the record (NaN:
    none)."""
    strain_age_s: NotRequired[npt.NDArray[np.float64]]
    """[record]: physics: the record's time less that sample's (0 to 24 ms); attached board: the
    host's read less the instant the sample's line ended (host clock)."""
    strain_stopped: NotRequired[bool]
    strain_reading: NotRequired[list[str]]
    """Beside a strain board: per gauge ``"calibrated"`` (the model's calibration file's gain)
    or ``"ESTIMATE"`` (``counts_per_microstrain``)."""
    """Attached strain board only: it failed or went away (the servo stream goes on)."""

class SimulatedStrain(TypedDict):
    time_s: float
    names: list[str]
    microstrain: npt.NDArray[np.float64]

class Settings(TypedDict):
    baud: int
    """Bus baud rate, bit/s."""
    cycle_hz: int
    telemetry_every: int
    """Telemetry every this many bus cycles outside streaming (0: off)."""
    stiffness_nm_rad: npt.NDArray[np.float64]
    """Per joint of the joint map, N m/rad (empty without a joint map)."""
    limits_rad: npt.NDArray[np.float64]
    """Per joint of the joint map: (lower, upper), rad."""

class Body(TypedDict):
    """The physics robot's body at one moment (``Board.body()``): world frame (x forward at the
    start, y left, z up), SI units, feet in the model's order (``feet``)."""

    time_s: float
    """Simulated time since power-on, s."""
    thorax_position_m: npt.NDArray[np.float64]
    """Origin of the thorax frame, m (3)."""
    thorax_orientation: npt.NDArray[np.float64]
    """Unit quaternion (w, x, y, z)."""
    thorax_rpy_rad: npt.NDArray[np.float64]
    """Roll, pitch, yaw of the thorax, rad (z-y-x Euler angles)."""
    thorax_velocity_m_s: npt.NDArray[np.float64]
    """Velocity of the thorax frame's origin, m/s (3)."""
    thorax_angular_velocity_rad_s: npt.NDArray[np.float64]
    """Angular velocity, rad/s, world axes (3)."""
    feet: list[str]
    """Leg of each foot row (``LF``, ``LM``, ...)."""
    foot_force_n: npt.NDArray[np.float64]
    """Force of the ground on each foot, N, [foot, xyz] (zero in the air)."""
    foot_contact: npt.NDArray[np.bool_]
    """Whether each foot touches something with a pushing normal force."""
    foot_slip_m_s: npt.NDArray[np.float64]
    """Speed of each foot's contact point along the surface, relative to it, m/s (0 in the air)."""

@final
class Board:
    """A board, the RP2040 emulator's pseudo-terminal, the in-process virtual robot or the
    physics robot."""

    @staticmethod
    def open(port: str, reply_timeout_s: float = 2.0) -> Board:
        """``/dev/ttyACM0`` or a pty path, ``virtual``, ``virtual:PATH``, ``physics`` or
        ``physics:SCENE``; checks versions. A ``virtual:PATH`` robot gets the settings ``dbot set``
        kept beside its store."""
    @property
    def port(self) -> str: ...
    @property
    def kind(self) -> Literal["serial", "virtual", "physics"]:
        """What the port is: a board or the emulator's pty, the virtual robot, the physics robot."""
    def body(self) -> Body:
        """The physics robot's body now; raises BoardError on any other kind of port."""
    def strain(self) -> SimulatedStrain | None:
        """The physics robot's simulated strain gauges, latest sample (every 24 ms of simulated
        time); None before the first bus cycle; raises BoardError on any other kind of port."""
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
    def gaits(self) -> list[dict[str, Any]]:
        """Every gait slot, as ``dbot gaits`` lists them: ``slot``, ``gait`` (None for an empty
        slot, else ``name``, ``crc``, ``joints``, ``slices``, ``period_s``, ``duty``), ``lost``
        (None, or what a damaged copy lost) and ``message`` (the loss in words)."""
    def status(self) -> Status:
        """State, fault, torque mask, playback position and the counters since boot
        (:class:`Counters`, named integers)."""
    def upload(self, slot: int, table: bytes, allow_infeasible: bool = False) -> int:
        """Checks the table as ``dbot upload --table`` checks a file (ValueError, the same words,
        for one the servos cannot follow at its planned period unless ``allow_infeasible``, then a
        UserWarning), uploads and verifies it; returns the bytes sent."""
    def upload_plan(
        self,
        slot: int,
        plan: Plan | PlanDir,
        name: str | None = None,
        torques: bool = False,
        allow_infeasible: bool = False,
    ) -> int:
        """Builds the step table of ``plan`` (``Plan.step_table(name or "dbot-gait", torques)``, or
        ``PlanDir.step_table(name)`` as ``dbot upload --plan DIR`` does) under the same rules and
        uploads it; returns the bytes sent. A refusal is ValueError with ``dbot``'s words and
        nothing reaches the board."""
    def play(
        self,
        slot: int,
        steps: int | None = None,
        period_scale: float = 1.0,
        backward: bool = False,
        allow_infeasible: bool = False,
    ) -> None:
        """Plays the gait in ``slot`` at ``period_scale`` times its planned period (0.1 to 10).
        Faster than planned (``period_scale`` < 1) the table's speeds at that period are checked
        against the servos as ``dbot run --period`` checks them: ValueError with the same words
        naming joint, speed and limit, or when the host does not hold the slot's table (one this
        ``Board`` uploaded, or in a ``virtual:PATH`` image); ``allow_infeasible`` plays it anyway
        with a UserWarning. Slower than planned needs no check."""
    def stop(self) -> str:
        """Stops the walk as ``dbot run`` and ``dbot record`` do: walking, at the end of the step;
        ramping, where the ramp got to; streaming, holding the last setpoint. Returns what it did,
        e.g. ``"the walk was stopped at the end of its step"``."""
    def queue_gait(
        self,
        slot: int,
        steps: int | None = None,
        period_scale: float = 1.0,
        backward: bool = False,
        allow_infeasible: bool = False,
    ) -> None:
        """Plays ``slot`` after the gait playing, at a step boundary without standing still;
        raises if it cannot follow (the reason names the legs or the joint, jump and bound).
        Faster than planned it meets ``play``'s period rule (ValueError, the same words, unless
        ``allow_infeasible``)."""
    def set_steer_family(self, straight: int, left: int, right: int, range: float) -> None:
        """The gaits ``steer`` blends: slots planned for headings 0, ``+range`` and ``-range``
        rad with the same leg phases, slices and period; raises with the reason if the board
        cannot blend them."""
    def steer(self, heading: float, speed: float = 1.0, allow_infeasible: bool = False) -> None:
        """The descending command: walk at ``heading`` rad (positive left, within the family's
        range) and ``speed`` (1 = as planned). From standing a steered walk starts (until
        ``stop``); while walking, the new heading and speed take over at the next step boundary.
        Faster than planned the family's tables are checked against the servos at that speed, as
        ``dbot steer --speed`` checks them: ``ValueError`` with the CLI's words when a servo could
        not follow one, or when this ``Board`` did not set the family or upload its tables (on
        ``virtual:PATH`` they are read from the image), unless ``allow_infeasible`` (then a
        ``UserWarning``)."""
    def set_platform(
        self, perturb: str, steps: int | None = None, platform_id: int | None = None
    ) -> dict[str, Any]:
        """Sets up the perturbation platform as ``dbot record --perturb`` does: ``perturb`` is
        ``LEG:STEP:MOVE`` (e.g. ``"RM:3:rise"``; steps from 0, MOVE ``rise`` or ``fall``) with
        the lab's positions (rest 2020, rise 2330, fall 1570 ticks, back to rest two cycles
        later) on servo ``platform_id`` (default: the lab's 22 unless the board's gait's joints
        use it, then the first free ID after theirs, 23 for the built-in model, as ``dbot``
        chooses). With ``steps`` (the run's) a step beyond it is refused; ``play`` refuses it on
        the board too. Raises before anything moves: a leg that is not a leg, a joint's ID, a
        platform servo that does not answer (naming its ID). Returns the trial record's
        perturbation: ``leg``, ``step``, ``rest``, ``moved_to``, and the ``platform_id`` used."""
    def clear_platform(self) -> None:
        """No perturbation platform any more (not while moving)."""
    def emergency_stop(self) -> None: ...
    def clear_fault(self) -> None: ...
    def set_torque(self, enable: bool) -> None:
        """Torque on or off for every servo (the board switches them together)."""
    def set_telemetry(self, every: int) -> None:
        """Telemetry every ``every`` bus cycles (0: off) outside streaming; streaming's
        proprioception follows ``enter_streaming(feedback_every=...)`` instead."""
    def set_health_limits(
        self,
        warn_temp_c: float | None = None,
        stop_temp_c: float | None = None,
        warn_low_v: float | None = None,
        stop_low_v: float | None = None,
        warn_high_v: float | None = None,
        stop_high_v: float | None = None,
    ) -> str:
        """The servos' heat and supply limits (warn, and stop a walk at the end of its step);
        unnamed limits keep the board's; refused (ValueError) in ``dbot set``'s words. Returns
        the limits as set."""
    def set_bus(self, baud: int, cycle_hz: int) -> None:
        """Bus baud (bit/s) and cycle rate (Hz). A baud change is undone and refused
        (ValueError, ``dbot set --baud``'s words) unless every servo answers at the new baud: the
        servos keep their own (EEPROM), set them first with ``dbot.Bench``."""
    def settings(self) -> Settings:
        """The board's run-time settings (as ``dbot status`` shows them)."""
    def set_stiffness(self, joint: int, stiffness_nm_rad: float) -> None:
        """Stiffness of one joint's servo (joint-map index), N m/rad: its P gain and the torque
        bias's divisor, as ``dbot set --stiffness --joint``. While walking the goals do not step:
        the bias moves to the new stiffness by at most the servo's one-cycle move per cycle."""
    def wait(self, seconds: float) -> None:
        """Lets time pass on the board's clock, keeping telemetry and proprioception."""
    def record_trial(
        self,
        out: str | PathLike[str],
        *,
        table: str | PathLike[str] | None = None,
        plan: str | PathLike[str] | None = None,
        play: int | None = None,
        steps: int | None = None,
        backward: bool = False,
        period: float | None = None,
        allow_infeasible: bool = False,
        seconds: float | None = None,
        notes: str = "",
        trial: str | None = None,
        substrate: str | None = None,
        strain: str | None = None,
        perturb: str | None = None,
        platform_id: int | None = None,
        every: int = 1,
    ) -> str:
        """Records a trial folder in ``out`` as ``dbot record --out`` does (the same library call;
        the keywords are its flags): returns the published folder. ``ValueError`` with the CLI's
        words before anything moves for a refusal (a ``period`` shorter than planned is checked
        against the servos as ``play(period_scale=)`` checks it; ``allow_infeasible=True`` plays
        it with a ``UserWarning``), ``dbot.BoardError`` for a failed link; Ctrl-C stops the walk,
        keeps the trial and raises ``KeyboardInterrupt`` naming it; a fault that stops the robot
        keeps the trial (outcome ``"faulted"``) and raises ``dbot.TrialFaulted`` naming it."""
        ...
    def record(
        self,
        duration_s: float,
        strain: str | None = None,
        strain_dir: str | PathLike[str] | None = None,
    ) -> Telemetry:
        """Telemetry for ``duration_s`` of board time. With ``strain`` (a strain board's port or
        ``"virtual"``; the servo board's port is refused) the strain board is calibrated, then
        recorded beside it into ``strain_dir`` as ``dbot record --strain`` does; the dict gains
        ``strain_time_s`` (on ``time_s``'s clock), ``strain_counts`` ([sample, 36] raw counts),
        ``strain_names`` and ``strain_error`` (why the strain stream stopped early, else None)."""
    def next_telemetry(self, timeout_s: float = 0.1) -> Telemetry | None:
        """The next playback telemetry record (one row, the keys of ``record``), waiting up to
        ``timeout_s`` of board time; None if none came. Records come every
        ``set_telemetry(every)`` bus cycles outside streaming."""
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
        """Targets from the next bus cycle on (rad, joint-map order); returns the sequence number.
        The board moves each goal toward its target by at most what the joint's servo moves in one
        cycle (no-load speed x cycle period: 37 ticks on an MX-28 at 100 Hz), so a target farther
        away is reached over several cycles, not in one."""
    def next_proprioception(self, timeout_s: float = 0.1) -> Proprioception | None: ...
    def drain_proprioception(self) -> Proprioception: ...
    def stream_step(
        self,
        angles_rad: npt.ArrayLike,
        torques_nm: npt.ArrayLike | None = None,
        cycles: int = 1,
        timeout_s: float = 0.1,
    ) -> tuple[dict[str, npt.NDArray[np.float64]], float] | None:
        """``DbotEnv.step``'s exchange in one call: the setpoint for each of ``cycles`` bus
        cycles, the last record's observation and its time (s); None if streaming stopped."""
    def last_stream_record(self) -> Proprioception | None: ...
    def attach_strain(
        self,
        port: str,
        strain_dir: str | PathLike[str],
        counts_per_microstrain: float | None = None,
        model: Model | None = None,
    ) -> None:
        """Starts the strain board on ``port`` beside this board (calibrated first, its first
        sample the baseline; recorded into ``strain_dir``): every proprioception record then
        carries ``strain_names``, ``strain_microstrain``, ``strain_age_s``, ``strain_stopped``
        and ``strain_reading``. Each gauge's gain is ``model``'s calibration file's when it has
        the gauge, else ``counts_per_microstrain`` (an ESTIMATE). ValueError for the servo
        board's own port, a gain that is not positive or missing, the physics robot, or a board
        that will not calibrate."""
    def detach_strain(self) -> str | None:
        """Stops the attached strain board, aligns its strain.csv with this board's clock;
        None, or why the strain stream stopped early."""

@final
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

class GaugeFit(TypedDict):
    gauge: str
    samples: int
    r2: float | None
    """R^2 over the step phase of counts above baseline against predicted microstrain."""
    gain: float | None
    """Counts per predicted microstrain, fitted through the origin (a calibration)."""
    rms_residual_counts: float | None
    reading: str
    """``"calibrated"``: the plan model's calibration file's gain; else ``"ESTIMATE"``."""
    reading_gain: float
    """The counts per microstrain the recorded strain was read through."""
    rms_microstrain: float | None
    """RMS of the recorded strain (through ``reading_gain``) against the prediction."""

def compare_strain(trial: str | PathLike[str], plan_dir: str | PathLike[str]) -> list[GaugeFit]:
    """A trial's strain against ``plan_dir``'s prediction per gauge (``dbot compare --strain``)."""

def walk_figures(walk: PhysicsWalk) -> WalkFigures:
    """The figures ``dbot demo`` prints for a walk, from what it recorded (SI units)."""

# -- pictures of a pose (render.rs) ------------------------------------------------------------

def camera_half_extent(model: Model, pose: dict[str, Any], scene: str = "flat") -> list[float]:
    """Camera half-extent (m, x y z) holding ``pose`` around its thorax on ``scene``."""

def render_pose(
    model: Model, pose: dict[str, Any], half_extent_m: list[float], scene: str = "flat"
) -> npt.NDArray[np.uint8]:
    """One RGB frame (420, 1200, 3) of ``pose`` (thorax_position_m, thorax_orientation (w, x, y,
    z), q (one angle per model joint), stance (one flag per foot), caption) on ``scene``."""

def write_walk_gif(
    model: Model, poses: list[dict[str, Any]], path: str | PathLike[str], scene: str = "flat",
    delay_ms: int = 100,
) -> int:
    """Writes ``poses`` as a looping GIF, the camera following the thorax; returns the frame count."""

# --- servo bench (python/src/bench.rs, board::bench; `dbot dxl`) ---
@final
class Bench:
    """Dynamixel servos on a USB serial adapter (U2D2) or `dbot sim-bus`, as `dbot dxl` reaches them."""

    @staticmethod
    def open(port: str, baud: int | str | None = None, reply_slack_us: int = 20000) -> Bench: ...
    @property
    def baud(self) -> int | None: ...
    def close(self) -> None:
        """Closes the port (opened exclusively) so ``dbot dxl`` or another ``Bench`` can use it; a
        later call opens it again."""
    def __enter__(self) -> Bench: ...
    def __exit__(self, *args: object) -> bool: ...
    def scan(self, max_id: int = 252) -> list[dict[str, Any]]: ...
    def read(
        self, id: int, field: str | None = None, addr: int | None = None, length: int | None = None
    ) -> dict[str, Any]: ...
    def write(
        self,
        id: int,
        value: int,
        field: str | None = None,
        addr: int | None = None,
        length: int | None = None,
    ) -> None: ...
    def setup(
        self,
        id: int,
        new_id: int | None = None,
        new_baud: int | None = None,
        return_delay_us: int | None = None,
    ) -> dict[str, Any]: ...

def identify(
    trials: list[str | PathLike[str]],
    model: Model | None = None,
    out: str | PathLike[str] | None = None,
    refine_replays: int = 0,
) -> Model: ...
def replay(trial: str | PathLike[str], model: Model | None = None) -> dict[str, Any]:
    """``dbot replay``: per joint position, velocity and load figures (``load_reading``) and,
    when the trial recorded strain, per gauge ``rms_microstrain``, ``r2``, ``reading`` and
    ``counts_per_microstrain`` (``gauges``)."""

def excitation(kind: str, model: Model | None = None) -> list[dict[str, Any]]:
    """The excitation trials of ``kind`` (``"suspended"`` or ``"standing"``) for ``model``, as
    ``dbot excite --kind KIND`` writes them: one dict per step table (``name``, ``kind``,
    ``dt_s``, ``period_s``, ``joint_names``, ``goals_rad``, ``segments``, ``table``)."""

def calibrate(
    trial: str | PathLike[str],
    model: Model | None = None,
    out: str | PathLike[str] | None = None,
    against: str = "plan",
) -> dict[str, Any]:
    """``dbot calibrate``: per joint the Present Load gain and offset, per gauge its counts per
    microstrain, fitted from a standing trial against the plan's prediction (``against="plan"``)
    or the trial replayed on the model's body (``"replay"``: a model ``identify`` fitted)
    (``joints`` and ``gauges``: ``name``, ``samples``, ``r2``, ``gain``, ``offset_nm``,
    ``kept``; ``against``); with ``out`` writes the calibration file a model file names
    (``calibration = "FILE"``)."""

def stand_in_standing_trial(out: str | PathLike[str], short: bool = False) -> dict[str, Any]:
    """The reading stand-in (load 0.8 x torque + 0.05 N m, gauge gains 0.3 + 0.02 x column)
    records the standing excitation with strain: ``trial``, ``model``, ``gauge_gains``."""

def stand_in_trials(
    out: str | PathLike[str], joints: list[str] | None = None, short: bool = False
) -> dict[str, Any]: ...

@final
class EnvStepper:
    """``DbotEnv.step`` on the physics robot in one call (made by ``DbotEnv.reset``): targets
    clipped to ``[low, high]`` (rad), torques to ``[-stall, stall]`` (N m), ``cycles`` bus cycles
    a step, each record awaited up to ``timeout_s``; the strain keys observed when ``strain``."""

    def __new__(
        cls,
        board: Board,
        low: npt.ArrayLike,
        high: npt.ArrayLike,
        stall: npt.ArrayLike,
        cycles: int,
        timeout_s: float,
        strain: bool,
        fall_height_m: float,
        fall_tilt_rad: float,
    ) -> EnvStepper: ...
    def step(
        self, angles_rad: npt.ArrayLike, torques_nm: npt.ArrayLike | None = None
    ) -> tuple[dict[str, npt.NDArray[np.float64]], dict[str, Any], float, bool] | None:
        """``(obs, info, x, fell)``: the observation, ``info`` (``time_s``, ``state``,
        ``body``), the thorax's world x (m) and the fall rule's verdict; None if streaming
        stopped."""

@final
class VectorOptions:
    """What every sub-environment of ``VectorCore`` is built with, as
    ``dbot.env.DbotEnv`` takes it (python/src/vector_sub.rs); ``table`` the step table's bytes."""

    def __new__(
        cls,
        table: bytes,
        scene: str,
        cycles_per_step: int,
        max_episode_steps: int,
        stiffness_nm_rad: float | None,
        settle_s: float,
        timeout_cycles: int,
        reply_timeout_s: float,
        fall_height_fraction: float,
        fall_tilt_rad: float,
        cheap_reset: bool = True,
    ) -> VectorOptions: ...

@final
class VectorCore:
    """N physics robots on ``threads`` worker threads, the GIL released, or with ``threads=0`` on
    the calling thread, the GIL held (the engine of ``dbot.env.VectorEnv``; python/src/vector.rs).
    Rows: a dict of arrays, first axis the sub-environment."""

    def __new__(
        cls,
        num_envs: int,
        threads: int,
        options: VectorOptions,
        low: list[float] | None = None,
        high: list[float] | None = None,
        stall: list[float] | None = None,
        obs_keys: list[str] | None = None,
    ) -> VectorCore: ...
    @property
    def num_envs(self) -> int: ...
    @property
    def threads(self) -> int: ...
    def reset(
        self,
        mask: npt.NDArray[np.bool_] | None = None,
        scene: str | None = None,
        stiffness_nm_rad: float | None = None,
    ) -> dict[str, Any]: ...
    def step(
        self,
        angles_rad: npt.NDArray[np.float64],
        torques_nm: npt.NDArray[np.float64] | None = None,
        reset: npt.NDArray[np.bool_] | None = None,
    ) -> dict[str, Any]: ...
    def step_env(
        self,
        angles_rad: npt.NDArray[np.float64],
        torques_nm: npt.NDArray[np.float64] | None = None,
    ) -> tuple[
        dict[str, npt.NDArray[np.float64]],
        npt.NDArray[np.float64],
        npt.NDArray[np.bool_],
        npt.NDArray[np.bool_],
        dict[str, Any],
        tuple[npt.NDArray[np.bool_], npt.NDArray[np.float64]] | None,
    ]: ...
    def close(self) -> None: ...

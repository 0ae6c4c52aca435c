"""Drosophibot II from Python: models, gait planning, boards, streaming setpoints.

Thin typed bindings over the Rust host libraries (``planner``, ``board`` crates) built with PyO3:

* :class:`Model` - an organism model (``Model.builtin("drosophibot2")``, ``Model.load(path)``).
* :func:`plan` - one planned step cycle; parameters in, NumPy arrays out (:class:`Plan`).
* :func:`plan_standing` - the robot standing still in its resting posture, solved: the angles,
  the torques of the bias, the foot forces and the gauges' predicted strain.
* :func:`excitation` - the excitation trials that identify the robot (``"suspended"``: per-joint
  steps and chirps, feet in the air; ``"standing"``: slow posture changes), each with its step
  table checked by the rules of any gait, as ``dbot excite`` writes them.
* :func:`identify` / :func:`replay` - the servo dynamics fitted to suspended excitation trials
  and the ground friction to walks whose feet slip (``dbot identify``), a trial replayed on the
  physics robot with per-joint R^2 and RMS (``dbot replay``); :func:`stand_in_trials` - the
  stand-in robot's trials (docs/identification.md); :func:`calibrate` - calibrated readings from
  a standing trial (``dbot calibrate``); :func:`stand_in_standing_trial` - a standing trial with
  strain of a stand-in of known gains.
* :func:`read_plan_dir` - a plan directory written by ``dbot plan`` / ``dbot demo`` (:class:`PlanDir`),
  with the same step table bytes as ``dbot table --plan``.
* :func:`read_trial` - a trial folder written by ``dbot record``: arrays with its trial.json.
* :func:`compare` - two plan directories or trials DoF by DoF (R^2 of angles and torques), as
  ``dbot compare A B``.
* :func:`compare_strain` - a trial's recorded strain against a plan's prediction, per gauge.
* :func:`physics_walk` / :func:`walk_figures` - walk a plan directory's gait on a fresh physics
  robot and compute the figures ``dbot demo`` prints for a walk (the ``lab`` crate's functions).
* :class:`Board` - a board, the RP2040 emulator's pseudo-terminal, the virtual robot
  (``Board.open("virtual")``) or the physics robot with a MuJoCo body (``Board.open("physics")``),
  with upload, playback, telemetry and the streaming mode
  (``enter_streaming``, ``send_setpoint``, ``next_proprioception``); ``Board.kind`` says which
  kind a port is and ``Board.body()`` reads the physics robot's simulated body (thorax pose and
  velocity, foot forces, contact, slip).
* :class:`Bench` - the servo bench of ``dbot dxl``: Dynamixel servos on a U2D2 or ``dbot sim-bus``
  (``Bench.open(port, baud=57600 or "auto")``, ``scan``, ``read``, ``write``, ``setup``).
* :func:`render_pose` / :func:`write_walk_gif` - the walk drawing of a simulated pose as RGB
  pixels or a GIF (the environment's ``rgb_array``).
* :mod:`dbot.env` - ``DbotEnv``, a Gymnasium environment over the physics robot or a board port
  with the firmware in the loop (needs the ``gymnasium`` package; imported on its own), and
  ``VectorEnv``, N physics robots stepped on Rust threads (:mod:`dbot.vector_env`; rollouts on
  Ray actors or a process pool holding one: :mod:`dbot.vector_pool`).
* :class:`DescendingEnv` (:mod:`dbot.env_descending`) - the environment's descending action mode:
  (heading, speed) in, the board blending its stored steering family; ``dbot.DescendingEnv``
  imports gymnasium on first use only.

Units are SI (m, rad, s, N m); arrays are indexed ``[slice, joint]`` / ``[record, joint]``.
"""

from ._native import (
    BUILTIN_MODELS,
    Bench,
    Board,
    BoardError,
    DbotError,
    Model,
    Plan,
    PhysicsWalk,
    PlanDir,
    TrialFaulted,
    __version__,
    calibrate,
    camera_half_extent,
    compare,
    compare_strain,
    doctor,
    excitation,
    identify,
    physics_walk,
    plan,
    plan_standing,
    read_plan_dir,
    read_trial,
    render_pose,
    replay,
    stand_in_standing_trial,
    stand_in_trials,
    walk_figures,
    write_walk_gif,
)

__all__ = [
    "BUILTIN_MODELS",
    "Bench",
    "Board",
    "BoardError",
    "DbotError",
    "DescendingEnv",
    "Model",
    "Plan",
    "PhysicsWalk",
    "PlanDir",
    "TrialFaulted",
    "__version__",
    "calibrate",
    "camera_half_extent",
    "compare",
    "compare_strain",
    "doctor",
    "excitation",
    "identify",
    "physics_walk",
    "plan",
    "plan_standing",
    "read_plan_dir",
    "read_trial",
    "render_pose",
    "replay",
    "stand_in_standing_trial",
    "stand_in_trials",
    "walk_figures",
    "write_walk_gif",
]


def __getattr__(name: str) -> object:
    # The environment imports gymnasium: only when it is asked for, so `import dbot` stays light.
    if name == "DescendingEnv":
        from .env_descending import DescendingEnv

        return DescendingEnv
    raise AttributeError(f"module 'dbot' has no attribute {name!r}")

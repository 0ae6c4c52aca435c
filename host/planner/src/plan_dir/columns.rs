//! The plan directory's file names and CSV columns, named once: the writers emit these headers and
//! the reader looks columns up by these names.

/// The plan's summary (a [`super::PlanJson`]).
pub const PLAN_JSON: &str = "plan.json";
/// The planned model in the TOML model format, so the directory is read without the model's source.
pub const MODEL_TOML: &str = "model.toml";
/// The model as URDF (for viewers; not read back).
pub const MODEL_URDF: &str = "model.urdf";
/// One row per slice and model joint.
pub const JOINTS_CSV: &str = "joints.csv";
/// One row per slice and leg.
pub const FEET_CSV: &str = "feet.csv";
/// Per slice and joint, the internal forces of the inverse dynamics (with dynamics only).
pub const JOINT_FORCES_CSV: &str = "joint_forces.csv";

/// joints.csv and feet.csv: slice index, from 0.
pub const SLICE: &str = "slice";
/// joints.csv and feet.csv: time of the slice, s.
pub const TIME_S: &str = "time_s";
/// joints.csv and feet.csv: leg name (`LF` ... `RH`).
pub const LEG: &str = "leg";
/// joints.csv and feet.csv: 1 while the leg is in stance, else 0.
pub const STANCE: &str = "stance";

/// joints.csv: joint kind (`ThC1` ... `TiTar`).
pub const JOINT: &str = "joint";
/// joints.csv: joint angle, rad.
pub const ANGLE_RAD: &str = "angle_rad";
/// joints.csv: joint velocity, rad/s.
pub const VELOCITY_RAD_S: &str = "velocity_rad_s";
/// joints.csv: joint acceleration, rad/s^2.
pub const ACCEL_RAD_S2: &str = "accel_rad_s2";
/// joints.csv with dynamics: actuator torque, N m.
pub const TORQUE_NM: &str = "torque_nm";
/// joints.csv with dynamics: servo command, angle + torque / servo stiffness, rad.
pub const COMMAND_RAD: &str = "command_rad";

/// feet.csv: foot position in the thorax frame (REP-103), m.
pub const FOOT_XYZ_M: [&str; 3] = ["x_m", "y_m", "z_m"];
/// feet.csv with dynamics: ground reaction force on the foot, thorax frame, N.
pub const GRF_XYZ_N: [&str; 3] = ["grf_x_n", "grf_y_n", "grf_z_n"];

/// joints.csv's columns before any extra ones, in file order.
pub const JOINTS_BASE: [&str; 8] = [
    SLICE,
    TIME_S,
    LEG,
    JOINT,
    ANGLE_RAD,
    VELOCITY_RAD_S,
    ACCEL_RAD_S2,
    STANCE,
];

/// feet.csv's columns before any extra ones, in file order.
pub const FEET_BASE: [&str; 7] = [
    SLICE,
    TIME_S,
    LEG,
    FOOT_XYZ_M[0],
    FOOT_XYZ_M[1],
    FOOT_XYZ_M[2],
    STANCE,
];

//! Organism models: rigid bodies connected by hinge joints in a tree rooted at the thorax, with foot
//! contact points, actuators, optional parallel springs and the servo map.
//!
//! Conventions (one place for all of them):
//! - SI units: m, kg, kg m^2, rad, N m / rad. Frames follow ROS REP-103: x forward, y left, z up.
//!   Imports from the paper's / AnimatLab's y-up frame convert at the importer.
//! - Body 0 is the thorax, the root. Every other body has exactly one proximal joint, and a body's
//!   frame is the frame of that joint: at angle `q` the child frame is `parent * origin * R(axis, q)`.
//! - A body's centre of mass and inertia are given in its own frame (inertia about the CoM).

mod types;

pub use types::*;

mod aproj;
mod builtin;
pub mod calibration;
mod error;
mod file;
mod file_write;
mod gauge_file;
mod gauges;
mod mjcf;
mod query;
mod ranges;
mod servo_params;
pub mod spring;
mod urdf;
mod validate;

pub use aproj::{ImportOptions, anim_to_rep, import_aproj, import_aproj_file, parse_joint_name};
pub use builtin::{BUILTIN_NAMES, builtin};
pub use calibration::{CalibrationFile, GaugeCalibration, JointCalibration, ReadingCalibration};
pub use error::ModelError;
pub use file::{ModelFile, from_toml_str, load};
pub use file_write::{rpy_of, to_toml_string};
pub use gauge_file::GaugeEntry;
pub use gauges::{Gauge, GaugeDirection, Material, Section};
pub use mjcf::{
    BALL_MASS_KG, DEFAULT_TIMESTEP_S, FOOT_RADIUS_M, MUJOCO_FLOOR, MjcfOptions, Scene,
    ServoActuator, hinge_order, joint_actuator, servo_actuator, to_mjcf,
};
pub use ranges::{DEFAULT_FOOT_FRICTION, FOOT_FRICTION};
pub use servo_params::{FieldRange, SERVO_FIELDS, ServoDynamics, ServoParams, ServoParamsEntry};
pub use spring::{SpringPreset, SpringSpec};
pub use urdf::to_urdf;

/// Longest leg chain (joints from thorax to foot) a model may have: the kinematics' fixed-size
/// solver handles up to this many.
pub const MAX_CHAIN: usize = 8;

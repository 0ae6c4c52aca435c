//! What one slice of the inverse dynamics needs, and the options of the solve.

use nalgebra::Vector3;

use crate::model::{Actuation, ActuatorKind, Model};

/// Motion of the thorax at a slice, in its own frame. The default is the paper's assumption:
/// constant velocity, no rotation. (A constant linear velocity changes no force.)
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ThoraxMotion {
    /// m/s.
    pub linear_velocity: Vector3<f64>,
    /// rad/s.
    pub angular_velocity: Vector3<f64>,
    /// m/s^2, of the thorax frame's origin.
    pub linear_acceleration: Vector3<f64>,
    /// rad/s^2.
    pub angular_acceleration: Vector3<f64>,
}

/// The state of one time slice. Per-joint vectors follow `model.joints`, per-foot vectors
/// `model.feet`; all vectors are in the thorax frame.
#[derive(Debug, Clone, PartialEq)]
pub struct SliceInput {
    /// Joint angles, rad (fixed joints included: their angle as planned).
    pub q: Vec<f64>,
    /// Joint velocities, rad/s.
    pub qd: Vec<f64>,
    /// Joint accelerations, rad/s^2.
    pub qdd: Vec<f64>,
    /// Whether each foot is in stance (swing feet get exactly zero GRF).
    pub stance: Vec<bool>,
    pub thorax: ThoraxMotion,
    /// Gravitational acceleration in the thorax frame, m/s^2 (an incline rotates it).
    pub gravity: Vector3<f64>,
    /// Outward contact normal (pointing from the ground into the foot) per foot; only used by the
    /// friction cone, push-only constraint and slip report. Need not be unit length.
    pub normals: Vec<Vector3<f64>>,
}

impl SliceInput {
    /// A static slice on flat ground, gravity -[`crate::terrain::G`] along z, all feet in stance.
    pub fn still(model: &Model, q: Vec<f64>) -> Self {
        let n = model.joints.len();
        Self {
            q,
            qd: vec![0.0; n],
            qdd: vec![0.0; n],
            stance: vec![true; model.feet.len()],
            thorax: ThoraxMotion::default(),
            gravity: Vector3::new(0.0, 0.0, -crate::terrain::G),
            normals: vec![Vector3::z(); model.feet.len()],
        }
    }
}

/// How the thorax is held.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Base {
    /// Free: the stance feet must hold it (the walking robot). Thorax equilibrium is enforced.
    #[default]
    Floating,
    /// Bolted to the world (a robot on a stand); the stand takes whatever the feet do not.
    Fixed,
}

/// Actuator torque limits per joint, N m (`None`: unlimited).
#[derive(Debug, Clone, PartialEq)]
pub enum TorqueLimits {
    /// MX-28 2.5 N m, MX-64 6.0 N m (stall torque at 12 V), generic actuators unlimited.
    FromActuators,
    /// One entry per joint of the model.
    PerJoint(Vec<Option<f64>>),
}

impl TorqueLimits {
    /// The limit of every joint of `model` (fixed joints: none).
    pub fn resolve(&self, model: &Model) -> Vec<Option<f64>> {
        match self {
            TorqueLimits::PerJoint(v) => v.clone(),
            TorqueLimits::FromActuators => model
                .joints
                .iter()
                .map(|j| match &j.actuation {
                    Actuation::Actuated { actuator, .. } => stall_torque(*actuator),
                    Actuation::Fixed { .. } => None,
                })
                .collect(),
        }
    }
}

/// Stall torque at 12 V from the Dynamixel e-manuals ([`protocol::ServoModel`]'s); none for a
/// generic actuator.
pub fn stall_torque(kind: ActuatorKind) -> Option<f64> {
    protocol::ServoModel::try_from(kind)
        .ok()
        .map(|m| f64::from(m.stall_torque_nm()))
}

/// Options of the inverse dynamics. The default is the paper's problem: no contact constraints,
/// no torque limits.
#[derive(Debug, Clone, PartialEq)]
pub struct DynamicsOptions {
    pub base: Base,
    /// Enforce a friction cone |f_t| <= mu f_n per stance foot (implies push-only).
    pub friction_cone: bool,
    /// Enforce f_n >= 0 per stance foot.
    pub push_only: bool,
    /// Friction coefficient for the cone and for the slip report. The default 0.5 is an assumed
    /// value for rubber-coated feet on sandpaper, not a measurement.
    pub mu: f64,
    /// Torque limits for the report; enforced only when `enforce_torque_limits` is set.
    pub torque_limits: TorqueLimits,
    pub enforce_torque_limits: bool,
    /// Solve slices on all cores (rayon).
    pub parallel: bool,
    /// Use Clarabel even when the problem has equalities only (otherwise solved directly).
    pub always_clarabel: bool,
}

impl Default for DynamicsOptions {
    fn default() -> Self {
        Self {
            base: Base::Floating,
            friction_cone: false,
            push_only: false,
            mu: 0.5,
            torque_limits: TorqueLimits::FromActuators,
            enforce_torque_limits: false,
            parallel: false,
            always_clarabel: false,
        }
    }
}

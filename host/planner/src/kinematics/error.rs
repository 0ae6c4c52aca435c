//! Kinematics errors, naming leg, slice and distance.

use crate::model::Leg;

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum KinematicsError {
    /// The foot target could not be reached within tolerance (joint limits or leg length).
    #[error(
        "leg {leg}: slice {slice}: target unreachable, {distance:.3e} m from the nearest foot position found"
    )]
    Unreachable {
        leg: &'static str,
        slice: usize,
        distance: f64,
    },
    #[error("leg {leg}: the model has no foot on this leg")]
    NoFoot { leg: &'static str },
    #[error("leg {leg}: chain of {len} joints; at most {max} supported")]
    ChainTooLong {
        leg: &'static str,
        len: usize,
        max: usize,
    },
    #[error("leg {leg}: resting posture: {problem}")]
    Posture { leg: &'static str, problem: String },
}

impl KinematicsError {
    pub(crate) fn unreachable(leg: Leg, slice: usize, distance: f64) -> Self {
        KinematicsError::Unreachable {
            leg: leg.name(),
            slice,
            distance,
        }
    }
}

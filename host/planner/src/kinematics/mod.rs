//! Kinematics of a [`Model`](crate::model::Model): forward kinematics of the whole tree, leg
//! Jacobians, a fast per-leg inverse-kinematics solver and the resting posture.
//!
//! Everything is expressed in the thorax frame (REP-103), which is the "world" of the planner: the
//! ground moves under a thorax that stays put.

mod chain;
mod error;
mod fk;
mod posture;

pub use chain::{IkOptions, LegChain};
pub use error::KinematicsError;
pub use fk::{Poses, forward, joint_angle, leg_jacobian};
pub use posture::{FootGoal, Posture, resting_posture};

pub use crate::model::MAX_CHAIN;

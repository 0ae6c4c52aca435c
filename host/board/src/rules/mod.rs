//! The rules that protect the robot, enforced by the library calls that build a step table
//! ([`build`]), upload one ([`upload`]), play or queue one faster than planned ([`period`]), steer faster than planned ([`steer`]), set a servo's
//! stiffness ([`stiffness`]) and change the bus baud ([`bus`]), so `dbot`, Python and any Rust caller refuse alike, with the same
//! words ([`RuleError`]'s Display). One override, [`Overrides::allow_infeasible`], lets a plan the
//! servos cannot follow through; what it let through comes back as an [`Overridden`] warning whose
//! words every door shows as they are.
//!
//! Joint limits are the table format's own rule: the table builder refuses a planned angle outside
//! its joint's limits (`protocol::gait::BuildError`), whichever door builds the table.

pub mod build;
pub mod bus;
mod error;
pub mod feasibility;
pub mod period;
pub mod slots;
pub mod steer;
pub mod stiffness;
pub mod upload;

pub use error::{Overridden, RuleError, Violations};

/// What the caller chose to let through.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Overrides {
    /// Build, upload, play or steer a table even when a servo cannot follow it (speed over the no-load
    /// speed, torque over stall or over the torque-speed line, an inverse-kinematics jump);
    /// `dbot --allow-infeasible`, Python `allow_infeasible=True`.
    pub allow_infeasible: bool,
}

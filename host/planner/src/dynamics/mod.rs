//! Inverse dynamics per time slice (paper section 2.2.2, equations 3 to 9) as a small QP.
//!
//! The paper stacks the Newton-Euler equations of all 33 bodies (198 rows, 210 unknown joint
//! forces and moments) and minimises the complementary energy V* = 1/2 sum (u . T)^2 / k with
//! fmincon. In a tree every joint wrench follows from the ground reaction forces (GRF) by one
//! backward Newton-Euler pass, so the only freedom is how the stance feet share the load. Here:
//!
//! 1. [`motion`]: forward recursion of orientations, angular velocities and accelerations (eqs. 3
//!    and 4 written as the exact rigid-body recursion) and CoM accelerations (eq. 6, analytically
//!    instead of by finite differences, so that they are consistent with the given q, qd, qdd).
//! 2. [`wrench`]: every body's required wrench m (a - g), I alpha + w x I w (the right side of eq. 7)
//!    and a backward pass that turns them plus the GRF into joint forces and moments (eq. 8).
//! 3. [`problem`]: unknowns = stance-foot GRF; actuated torques are affine in them; the thorax
//!    equilibrium is 6 equalities; optional friction cones, push-only feet and torque limits.
//!    The optimum is unique when each stance leg's foot-force-to-torque map has full rank,
//!    which is checked (no regulariser is used).
//! 4. [`solve`]: the QP per slice (direct null-space solve or Clarabel), then the outputs.
//!
//! All vectors are in the thorax frame of the slice (REP-103: x forward, y left, z up), about
//! which the thorax's own motion is given. Joint force / moment = what the parent body exerts on
//! the child, moment about the joint's origin.

mod error;
mod from_plan;
mod infeasible;
mod input;
pub mod motion;
pub mod output;
pub mod problem;
mod report;
mod solve;
pub mod summary;
pub mod wrench;

pub use error::DynamicsError;
pub use from_plan::plan_inputs;
pub use input::{Base, DynamicsOptions, SliceInput, ThoraxMotion, TorqueLimits};
pub use report::{ConstraintReport, Saturation, Slip};
pub use solve::{
    CycleSolution, SliceSolution, slice_problem, solve_cycle, solve_problem, solve_slice,
};
pub use summary::DynamicsSummary;

//! Drosophibot II in MuJoCo 3.17.0 (through mujoco-rs 7.0.0): the model's MJCF
//! (`planner::model::to_mjcf`) loaded as a [`Plant`] whose actuators behave like the MX servos'
//! position controllers ([`servo`], step by step [`drive`]: deadband, PID, torque-speed line,
//! backlash), and the [`PhysicsRobot`]: the firmware library's board over
//! the simulated Dynamixel bus driving that plant, time advancing with the bus cycles: the board's
//! virtual robot with a [`PhysicsRobot`] as its servo dynamics, behind the virtual robot's
//! transport ([`PhysicsTransport`]). Its [`Body`] (thorax pose and velocity, foot contacts,
//! simulated time) is a typed value, its strain gauges are measured beside it
//! ([`SimulatedGauges`]), and the ground under its feet is a [`Substrate`] with its friction
//! ESTIMATE. [`open`] opens a robot of any kind by port name, its kind
//! kept in the type ([`Robot`], [`RobotLink`]).
//!
//! MuJoCo comes from scripts/setup.d/20-mujoco.sh (see build.rs).

mod body;
pub mod drive;
mod error;
mod figures;
mod gauges;
mod plant;
pub mod platform;
mod robot;
pub mod servo;
pub mod substrate;
mod timestep;
mod transport;
mod walk_log;

pub use body::{Body, Foot, Thorax};
pub use error::PhysicsError;
pub use figures::{Figures, Monitor};
pub use gauges::{STRAIN_SAMPLE_S, SimulatedGauges, SimulatedStrain};
pub use plant::{GRAVITY_RAMP_S, Plant, PlantJoint, PlantState};
pub use platform::{HEIGHT_PER_TICK_M, LEVEL_TICKS};
pub use robot::PlatformPlace;
pub use robot::{PhysicsBoard, PhysicsRobot, PhysicsState, PhysicsTransport, TIMESTEP_S};
pub use substrate::Substrate;
pub use timestep::{Stiffest, stiffest_joint};
pub use transport::{OpenError, Robot, RobotLink, open, open_physics, open_within, physics_body};
pub use walk_log::{WalkLog, WalkSample};

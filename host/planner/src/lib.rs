//! The Drosophibot II planner: organism models, terrain, gait, kinematics, inverse dynamics (a QP
//! per slice), predicted gauge strain, robot-versus-fly analysis, the step table built from a plan, the excitation
//! trials that identify the robot, and the planner's own
//! file formats (model TOML / .aproj / URDF, the plan directory). Pure computation and its formats:
//! no CLI, no board I/O, no plots (those live in the `board`, `report` and `dbot` crates).

pub mod analysis;
pub mod dynamics;
pub mod excitation;
pub mod gait;
pub mod kinematics;
pub mod model;
pub mod number;
pub mod plan;
pub mod plan_dir;
pub mod qp;
pub mod strain;
pub mod terrain;

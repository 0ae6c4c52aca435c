//! x
pub use mujoco_rs;

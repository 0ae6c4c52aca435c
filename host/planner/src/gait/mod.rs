//! Stepping: parameters (table 1 of the paper), gaits as phase offsets, and footpaths (stance
//! lines moved by the ground's motion, quintic swing), and curves as a turn per step and a radius.

mod footpath;
mod params;
mod phase;
mod presets;
mod quintic;
mod turning;

pub use footpath::{Footpath, GroundMotion};
pub use params::{ParamError, ParamsFile, PerPair, Placement, StepParams};
pub use phase::Gait;
pub use presets::{DEFAULT_PRESET, PRESETS, SERVO_SAFE_SWING_S};
pub use quintic::Quintic;
pub use turning::{MAX_RADIUS_M, MAX_TURN_DEG, Turn};

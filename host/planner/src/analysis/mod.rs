//! Robot-versus-fly analysis: R-squared of linear regressions between the angle and torque
//! traces of common DoF of two plans (tables S2 to S8 of the paper), summed DoF where one
//! organism moves several joints in one plane, and the torque scaling of a speed sweep.

mod compare;
pub mod paper;
mod regression;
mod sweep;

pub use compare::{ComparisonRow, DofTrace, compare};
pub use regression::{r_squared, resample_periodic};
pub use sweep::{SweepError, SweepPoint, SweepRegime, classify_sweep, sweep_point};

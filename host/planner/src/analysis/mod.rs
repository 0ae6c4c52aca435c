//! Robot-versus-fly analysis: R-squared of linear regressions ([`fit::regression_r2`]) between the angle and torque
//! traces of common DoF of two plans (tables S2 to S8 of the paper), summed DoF where one
//! organism moves several joints in one plane, and the torque scaling of a speed sweep.

mod compare;
pub mod fit;
pub mod paper;
mod resample;
mod sweep;

pub use compare::{ComparisonRow, DofTrace, compare};
pub use resample::resample_periodic;
pub use sweep::{SweepError, SweepPoint, SweepRegime, classify_sweep, sweep_point};

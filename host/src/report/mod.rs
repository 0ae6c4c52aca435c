//! Reports of a plan: CSV tables (with room for columns the dynamics adds) and plots.

mod bitmap;
mod csv_out;
pub mod legend;
pub mod number;
mod plots;
pub mod robot;
pub mod style;

/// What each file of a plan directory holds (columns, units, conventions): README.md beside them.
pub const PLAN_README: &str = include_str!("plan_readme.md");

pub use bitmap::Bitmap;
pub use csv_out::{ExtraColumn, ReportError, write_feet_csv, write_joints_csv};
pub use plots::{plot_feet, plot_footfall, plot_joint_angles};

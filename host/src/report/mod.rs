//! Reports of a plan: CSV tables (with room for columns the dynamics adds) and plots.

mod bitmap;
mod csv_out;
mod plots;
pub mod robot;
pub mod style;

pub use bitmap::Bitmap;
pub use csv_out::{ExtraColumn, ReportError, write_feet_csv, write_joints_csv};
pub use plots::{plot_feet, plot_footfall, plot_joint_angles};

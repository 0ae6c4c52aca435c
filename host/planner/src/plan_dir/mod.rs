//! The plan directory a plan is written to and read back from: joints.csv, feet.csv (and, with the
//! inverse dynamics, their extra columns).

mod csv_out;

pub use csv_out::{ExtraColumn, ReportError, write_feet_csv, write_joints_csv};

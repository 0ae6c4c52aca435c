//! Recording what the board did: telemetry as a tidy CSV (one row per bus cycle and joint, written
//! as it arrives so a board that vanishes leaves every row received so far), per-step statistics of
//! measured against modelled torque, and plots (the paper's figure 5, commanded vs present angles).

mod capture;
mod csv_out;
mod gaps;
mod joints;
mod names;
mod plots;
mod stats;

pub use capture::{CaptureError, Ended, Until, capture, capture_while};
pub use csv_out::{CSV_HEADER, Recorder, Row, TELEMETRY_README};
pub use gaps::missing_cycles;
pub use joints::{JointMeta, joints_of_table};
pub use names::joint_names;
pub use plots::{plot_angles, plot_torques};
pub use stats::{JointTracking, PhaseStats, phase_stats, tracking};

//! Recording what the board did: telemetry as a tidy CSV (one row per bus cycle and joint, written
//! as it arrives so a board that vanishes leaves every row received so far), per-step statistics of
//! measured against modelled torque, and the one way to stop a walk ([`stop_walk`]). Its plots live in the `report` crate (`report::recording`).

mod capture;
mod csv_out;
mod gaps;
mod joints;
mod names;
mod stats;
mod stop;

pub use capture::{
    CaptureError, Ended, FaultSeen, Until, capture, capture_until_standing, capture_while,
    check_telemetry_rate, set_recording_rate,
};
pub use csv_out::{
    CSV_HEADER, CSV_HEADER_BEFORE_HEALTH, CSV_HEADER_BEFORE_PLATFORM, CSV_HEADER_BEFORE_RUN_STATE,
    Recorder, Row, TELEMETRY_README,
};
pub use gaps::{missing_cycles, missing_words};
pub use joints::{JointMeta, held_stiffness, joints_of_table};
pub use names::{joint_names, joint_names_by_ids};
pub use stats::{JointTracking, PhaseStats, per_slice, phase_stats, tracking};
pub use stop::{Stopped, stop_walk};

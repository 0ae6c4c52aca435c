//! Test kit (feature `std`): what the firmware's own tests, its whole-board integration tests
//! (`firmware/tests/`) and the host's virtual-robot tests share.
//!
//! - [`clock`]: a clock whose waits end at once (tests with no wall time).
//! - [`gait`]: the synthetic 22-joint gait and the goals it must produce, computed independently.
//! - [`rig`]: the whole board (link, controller, bus loop, bus master, NOR flash double) on the
//!   dynamixel crate's simulated half-duplex wire with 22 virtual servos, and the host's side of
//!   the conversation (ask, upload, play, run bus cycles).

pub mod clock;
pub mod gait;
pub mod rig;

pub use gait::{JOINTS, STIFFNESS, SyntheticGait};

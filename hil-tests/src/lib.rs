//! Hardware-in-the-loop support: reading the firmware image and driving the real firmware binary end
//! to end, in the RP2040 emulator (hil-tests/runner, Node + rp2040js) or on a real board.
//!
//! A test: `let Some(board) = Target::start("name", Options::default())? else { return Ok(()) };`
//! then talk to `board.port()` like to `/dev/ttyACM0` and read `board.wait_for_log(..)`; emulator-only
//! controls (reset, flash file, fault injection, bus trace) are on `board.emulator()`.

pub mod bus_trace;
pub mod drive;
pub mod emulator;
pub mod gait;
pub mod image;
pub mod link;
pub mod paths;
pub mod pty;
pub mod servo_bus;
pub mod state_log;
pub mod target;

pub use emulator::{BusBurst, Echo, Emulator, LogLine, Options, TracedBurst, UsbOut};
pub use target::Target;

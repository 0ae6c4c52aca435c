//! The in-process virtual robot: the firmware library's controller and link dispatcher (the same
//! code the RP2040 runs) on a NOR flash double, simulated servos carrying the planned torques as
//! their loads, and a simulated clock. `--port virtual` talks to it through [`VirtualTransport`];
//! `--port virtual:PATH` keeps its flash in a file between commands.

mod board;
mod image;
mod transport;

pub use board::{FLASH_SECTORS, SLOTS, VirtualFlash, VirtualRobot};
pub use image::{IMAGE_LEN, ImageError};
pub use transport::VirtualTransport;

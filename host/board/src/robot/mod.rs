//! The in-process virtual robot: the firmware library's `Board` (the same controller, bus loop and
//! link dispatcher the RP2040 runs) on a NOR flash double, the robot's fixed servo chain carrying
//! the planned torques as their loads, and a simulated clock. `--port virtual` talks to it through [`VirtualTransport`];
//! `--port virtual:PATH` keeps its flash in a file between commands; [`pty::RobotPtyServer`] serves one
//! on a pseudo-terminal.

mod board;
mod flash;
pub(crate) mod image;
pub mod pty;
mod servos;
mod transport;

pub use board::{ROBOT_SERVOS, VirtualBoard, VirtualRobot, robot_chain, robot_servos};
pub use flash::{FLASH_SECTORS, SLOTS, VirtualFlash};
pub use image::{IMAGE_LEN, ImageError};
pub use servos::{PlannedLoads, ServoDynamics};
pub use transport::VirtualTransport;

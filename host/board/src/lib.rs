//! Everything on the host that talks to a board or runs one: the link (serial port, pseudo-terminal,
//! USB device discovery, transport, upload, streaming), the host's Dynamixel bus ends, recording
//! (capture, per-step statistics, telemetry CSV), the in-process virtual robot, and the lab's strain
//! board (driver, recorder, virtual board).

pub mod bus;
pub mod files;
pub mod link;
pub mod port;
pub mod record;
pub mod robot;
pub mod strain;

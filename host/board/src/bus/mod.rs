//! The host's Dynamixel bus ends: a virtual servo chain served on a pseudo-terminal at wall-clock
//! wire speed ([`pty`], behind `dbot sim-bus`), and a client for a USB serial adapter such as the
//! U2D2 that runs the same [`dynamixel::master::BusMaster`] as the firmware ([`serial`]).

pub mod pty;
pub mod serial;

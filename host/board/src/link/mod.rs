//! The link to a board: a byte-stream [`Transport`] with timeouts (a serial port, a pseudo-terminal,
//! or the in-process virtual robot) and the typed [`Board`] client over `protocol::Client`.
//!
//! Everything above the transport is the same for a real board, the RP2040 emulator's bridge and
//! the virtual robot, so `dbot` commands behave identically on all three.

mod board;
mod devices;
mod error;
mod serial;
mod stream;
mod transport;
mod upload;
mod version;

pub use board::{BOOT_WAIT, Board, DEFAULT_REPLY_TIMEOUT, request_name};
pub use devices::{BoardPort, list_boards};
pub use error::LinkError;
pub use serial::SerialTransport;
pub(crate) use serial::{explain_open_error, is_gone, not_a_port};
pub use stream::{SetpointError, setpoint_from_si};
pub use transport::{Transport, TransportError};
pub use upload::{UploadReport, Uploaded};

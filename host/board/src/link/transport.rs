//! The seam under the board client: a byte stream with read timeouts.
//!
//! Timeouts are in the transport's own time: wall-clock time for a serial port, simulated time for
//! the virtual robot (which advances its clock while the host waits, so it runs much faster than
//! real time).

use std::fmt::Debug;
use std::time::Duration;

/// Why bytes could not be moved.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum TransportError {
    /// The other end is gone (USB unplugged, pseudo-terminal closed, virtual robot switched off).
    #[error("the link closed: {reason}")]
    Closed { reason: String },
    /// Any other I/O failure.
    #[error(transparent)]
    Io(#[from] std::io::Error),
}

/// A byte stream to a board.
pub trait Transport: Debug {
    /// Writes every byte of `bytes`.
    fn send(&mut self, bytes: &[u8]) -> Result<(), TransportError>;
    /// Reads whatever arrives within `timeout` into `buf`; `Ok(0)` when nothing came in time.
    fn recv(&mut self, buf: &mut [u8], timeout: Duration) -> Result<usize, TransportError>;
    /// Where the link goes, for messages (`/dev/ttyACM0`, `virtual`).
    fn name(&self) -> &str;
    /// The transport's clock since it opened: wall time for a port, simulated time for the
    /// virtual robot. Reply timeouts are measured on it.
    fn now(&self) -> Duration;
    /// Ends the session cleanly (the virtual robot writes its flash image). Nothing for a port.
    fn shutdown(&mut self) -> Result<(), TransportError> {
        Ok(())
    }
}

impl<T: Transport + ?Sized> Transport for Box<T> {
    fn send(&mut self, bytes: &[u8]) -> Result<(), TransportError> {
        (**self).send(bytes)
    }
    fn recv(&mut self, buf: &mut [u8], timeout: Duration) -> Result<usize, TransportError> {
        (**self).recv(buf, timeout)
    }
    fn name(&self) -> &str {
        (**self).name()
    }
    fn now(&self) -> Duration {
        (**self).now()
    }
    fn shutdown(&mut self) -> Result<(), TransportError> {
        (**self).shutdown()
    }
}

//! A serial port as a [`Transport`]: the board's USB CDC-ACM port, or any pseudo-terminal that
//! carries the same frames (the RP2040 emulator's bridge).

use std::io::{ErrorKind, Read, Write};
use std::time::{Duration, Instant};

use super::transport::{Transport, TransportError};

/// Baud rate asked of the port. CDC-ACM ignores it (USB runs at its own speed); a pseudo-terminal
/// accepts any value.
pub const LINK_BAUD: u32 = 115_200;

/// An open serial port.
#[derive(Debug)]
pub struct SerialTransport {
    path: String,
    port: Box<dyn serialport::SerialPort>,
    opened: Instant,
}

impl SerialTransport {
    /// Opens `path` (e.g. `/dev/ttyACM0` or a pseudo-terminal's path).
    pub fn open(path: &str) -> Result<Self, TransportError> {
        let port = serialport::new(path, LINK_BAUD)
            .timeout(Duration::from_millis(100))
            .open()
            .map_err(|e| TransportError::Io(std::io::Error::other(format!("{path}: {e}"))))?;
        Ok(Self {
            path: path.to_owned(),
            port,
            opened: Instant::now(),
        })
    }
}

impl Transport for SerialTransport {
    fn send(&mut self, bytes: &[u8]) -> Result<(), TransportError> {
        self.port
            .write_all(bytes)
            .and_then(|()| self.port.flush())
            .map_err(|e| closed_or_io(&self.path, e))
    }

    fn recv(&mut self, buf: &mut [u8], timeout: Duration) -> Result<usize, TransportError> {
        // A zero timeout would make serialport block; poll for the shortest time instead.
        let timeout = timeout.max(Duration::from_millis(1));
        self.port
            .set_timeout(timeout)
            .map_err(|e| TransportError::Io(e.into()))?;
        match self.port.read(buf) {
            // A read that returns nothing although poll said readable: the other end hung up.
            Ok(0) => Err(TransportError::Closed {
                reason: format!("{}: end of file", self.path),
            }),
            Ok(n) => Ok(n),
            Err(e) if e.kind() == ErrorKind::TimedOut || e.kind() == ErrorKind::WouldBlock => Ok(0),
            Err(e) if e.kind() == ErrorKind::Interrupted => Ok(0),
            Err(e) => Err(closed_or_io(&self.path, e)),
        }
    }

    fn name(&self) -> &str {
        &self.path
    }

    fn now(&self) -> Duration {
        self.opened.elapsed()
    }
}

/// Errors that mean the device went away (USB unplug gives EIO or ENXIO, a closed pty EIO or a
/// broken pipe) become [`TransportError::Closed`].
fn closed_or_io(path: &str, e: std::io::Error) -> TransportError {
    let gone = matches!(
        e.kind(),
        ErrorKind::BrokenPipe | ErrorKind::UnexpectedEof | ErrorKind::NotConnected
    ) || matches!(
        e.raw_os_error(),
        Some(5 /* EIO */) | Some(6 /* ENXIO */) | Some(19 /* ENODEV */)
    );
    if gone {
        TransportError::Closed {
            reason: format!("{path}: {e}"),
        }
    } else {
        TransportError::Io(e)
    }
}

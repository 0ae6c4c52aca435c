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
    /// Opens `path` (e.g. `/dev/ttyACM0` or a pseudo-terminal's path). The error says what is
    /// wrong with the path in words a user can act on (it does not repeat the path).
    pub fn open(path: &str) -> Result<Self, TransportError> {
        if let Some(e) = not_a_port(path) {
            return Err(TransportError::Io(e));
        }
        let port = serialport::new(path, LINK_BAUD)
            .timeout(Duration::from_millis(100))
            .open()
            .map_err(|e| TransportError::Io(explain_open_error(path, e)))?;
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

/// Why `path` cannot be a serial port, found before trying to open it (a missing device or a
/// regular file would otherwise be reported as an OS error code's text such as "Not a typewriter").
pub(crate) fn not_a_port(path: &str) -> Option<std::io::Error> {
    use std::io::Error;
    match std::fs::metadata(path) {
        Err(e) if e.kind() == ErrorKind::NotFound => Some(Error::new(
            ErrorKind::NotFound,
            "no such device (is the board plugged in and powered? `dbot devices` lists the boards)",
        )),
        Err(e) if e.kind() == ErrorKind::PermissionDenied => Some(permission_denied()),
        Err(_) => None,
        Ok(m) if m.is_dir() => Some(Error::new(
            ErrorKind::InvalidInput,
            "is a directory, not a serial port",
        )),
        Ok(m) if m.is_file() => Some(Error::new(
            ErrorKind::InvalidInput,
            "is a regular file, not a serial port",
        )),
        Ok(_) => None,
    }
}

fn permission_denied() -> std::io::Error {
    std::io::Error::new(
        ErrorKind::PermissionDenied,
        "permission denied (on Linux, add yourself to the group that owns the port, usually \
         `dialout`, and log in again)",
    )
}

/// The serialport crate's open error, in words: a device that exists but is not a terminal, a
/// port another program holds, no permission. (The crate's error keeps only the OS message, so
/// the cases are told apart by looking at the device again.)
pub(crate) fn explain_open_error(path: &str, e: serialport::Error) -> std::io::Error {
    use std::io::Error;
    let io: Error = e.into();
    if io.kind() == ErrorKind::PermissionDenied {
        return permission_denied();
    }
    if let Some(false) = is_terminal(path) {
        return Error::new(
            ErrorKind::InvalidInput,
            "is not a serial port (the device is not a terminal)",
        );
    }
    if io.raw_os_error() == Some(nix::libc::EBUSY) || io.to_string().contains("busy") {
        return Error::new(
            ErrorKind::ResourceBusy,
            "is busy: another program (a terminal, ModemManager, another dbot) holds it",
        );
    }
    Error::new(io.kind(), format!("cannot open it: {io}"))
}

/// Whether `path` opens as a terminal (`None`: it does not open at all). Non-blocking and without
/// becoming the controlling terminal, so it neither waits for a modem nor changes any setting.
fn is_terminal(path: &str) -> Option<bool> {
    use std::io::IsTerminal as _;
    use std::os::unix::fs::OpenOptionsExt as _;
    let f = std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .custom_flags(nix::libc::O_NOCTTY | nix::libc::O_NONBLOCK)
        .open(path)
        .ok()?;
    Some(f.is_terminal())
}

/// Errors that mean the device went away (USB unplug gives EIO or ENXIO, a closed pty EIO or a
/// broken pipe) become [`TransportError::Closed`].
fn closed_or_io(path: &str, e: std::io::Error) -> TransportError {
    if is_gone(&e) {
        TransportError::Closed {
            reason: format!("{path}: {e}"),
        }
    } else {
        TransportError::Io(e)
    }
}

/// Whether an I/O error means the device went away (USB unplug gives EIO or ENXIO, a closed pty
/// EIO or a broken pipe). Also the strain board's test for an unplugged board.
pub(crate) fn is_gone(e: &std::io::Error) -> bool {
    matches!(
        e.kind(),
        ErrorKind::BrokenPipe | ErrorKind::UnexpectedEof | ErrorKind::NotConnected
    ) || matches!(
        e.raw_os_error(),
        Some(5 /* EIO */) | Some(6 /* ENXIO */) | Some(19 /* ENODEV */)
    )
}

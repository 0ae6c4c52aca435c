//! What the bus master returns: per-servo feedback or fault, cycle statistics, errors.

use crate::encode::EncodeError;
use crate::instruction::StatusError;

/// One servo's goal for a bus cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Goal {
    pub id: u8,
    /// Goal Position in ticks.
    pub position: i32,
}

/// Registers 126..=135 of one servo.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Feedback {
    /// Present Load (MX-28, 0.1 %) or Present Current (MX-64, ~3.36 mA); see [`crate::units`].
    pub load: i16,
    /// Present Velocity, 0.229 rev/min.
    pub velocity: i32,
    /// Present Position, ticks.
    pub position: i32,
    /// Alert bit of the status: a hardware error is latched (read Hardware Error Status).
    pub alert: bool,
}

impl Feedback {
    /// Decodes the 10 bytes at 126..=135.
    pub fn from_bytes(data: &[u8; 10], alert: bool) -> Self {
        Self {
            load: i16::from_le_bytes([data[0], data[1]]),
            velocity: i32::from_le_bytes([data[2], data[3], data[4], data[5]]),
            position: i32::from_le_bytes([data[6], data[7], data[8], data[9]]),
            alert,
        }
    }
}

/// Why one servo's reply is missing or unusable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum ReplyFault {
    /// No reply before the deadline.
    Timeout,
    /// A packet carrying this ID failed the CRC check.
    Crc,
    /// A packet with a wrong length (LEN field or data length).
    Malformed,
    /// The servo reported an error number (bits 0..6); Alert alone is not a fault.
    Status(StatusError),
}

/// Per-servo result of a cycle.
pub type Reply = Result<Feedback, ReplyFault>;

/// Statistics of one bus cycle, times from the master's clock in microseconds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CycleStats {
    pub start_us: u64,
    /// When the direction pin was released (last stop bit of the request sent).
    pub tx_end_us: u64,
    pub end_us: u64,
    pub ok: u8,
    /// Replies that were good but carried the Alert bit.
    pub alerts: u8,
    pub timeouts: u8,
    pub crc_errors: u8,
    pub malformed: u8,
    pub status_errors: u8,
    /// Instruction packets seen on the wire (own echo) and skipped.
    pub echo_frames: u8,
    /// Status packets from IDs not asked (or asked twice), ignored.
    pub stray_frames: u8,
    /// Bytes the parser dropped as garbage during the cycle.
    pub garbage_bytes: u32,
    /// Bytes already waiting before the request was sent (a late reply of an earlier exchange),
    /// discarded.
    pub stale_bytes: u32,
}

impl CycleStats {
    pub fn duration_us(&self) -> u64 {
        self.end_us - self.start_us
    }
}

/// A failure of the whole bus operation (as opposed to one servo's reply).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum BusError {
    /// The UART failed.
    Io(embedded_io_async::ErrorKind),
    /// The request could not be encoded.
    Encode(EncodeError),
    /// The result slice is shorter than the list of servos.
    ResultsTooShort { servos: usize, results: usize },
    /// More servos in one request than [`super::MAX_SERVOS`].
    TooManyServos { servos: usize, max: usize },
    /// A single-servo transaction's reply was missing or bad.
    Reply { id: u8, fault: ReplyFault },
    /// A read returned a different number of bytes than asked.
    DataLength { id: u8, expected: usize, got: usize },
}

impl From<EncodeError> for BusError {
    fn from(e: EncodeError) -> Self {
        BusError::Encode(e)
    }
}

/// A servo's answer to Ping.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PingReply {
    pub id: u8,
    pub model_number: u16,
    pub firmware: u8,
    pub error: StatusError,
}

/// Bus master timing settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MasterConfig {
    /// Line rate in bit/s; one byte takes 10 bit times on the wire.
    pub baud: u32,
    /// Time allowed for each reply beyond its own wire time, counted from the end of the request or
    /// the previous reply: must cover the servos' Return Delay Time plus their turnaround.
    pub reply_slack_us: u32,
}

impl MasterConfig {
    /// 1 Mbit/s with slack for the default Return Delay Time (500 us) plus 500 us.
    pub const fn new(baud: u32) -> Self {
        Self {
            baud,
            reply_slack_us: 1_000,
        }
    }

    /// Wire time of `bytes` bytes in microseconds (rounded up).
    pub const fn wire_time_us(&self, bytes: usize) -> u32 {
        ((bytes as u64 * 10 * 1_000_000).div_ceil(self.baud as u64)) as u32
    }
}

impl core::fmt::Display for ReplyFault {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            ReplyFault::Timeout => f.write_str("no reply before the deadline"),
            ReplyFault::Crc => f.write_str("reply failed the CRC check"),
            ReplyFault::Malformed => f.write_str("reply has a wrong length"),
            ReplyFault::Status(e) => match e.number() {
                Some(n) => write!(f, "servo reports {} (status byte 0x{:02X})", n.name(), e.0),
                None => write!(f, "servo status 0x{:02X}", e.0),
            },
        }
    }
}

impl core::fmt::Display for BusError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            BusError::Io(kind) => write!(f, "UART error: {}", io_words(*kind)),
            BusError::Encode(e) => write!(f, "cannot encode the request: {e}"),
            BusError::ResultsTooShort { servos, results } => {
                write!(
                    f,
                    "{servos} servos asked but room for only {results} results"
                )
            }
            BusError::TooManyServos { servos, max } => {
                write!(f, "{servos} servos in one request, at most {max}")
            }
            BusError::Reply { id, fault } => write!(f, "servo ID {id}: {fault}"),
            BusError::DataLength { id, expected, got } => {
                write!(
                    f,
                    "servo ID {id}: returned {got} data bytes, expected {expected}"
                )
            }
        }
    }
}

impl core::error::Error for BusError {}

/// An I/O error kind in words.
fn io_words(kind: embedded_io_async::ErrorKind) -> &'static str {
    use embedded_io_async::ErrorKind as K;
    match kind {
        K::NotFound => "not found",
        K::PermissionDenied => "permission denied",
        K::ConnectionRefused => "connection refused",
        K::ConnectionReset => "connection reset",
        K::ConnectionAborted => "connection aborted",
        K::NotConnected => "not connected",
        K::AddrInUse => "address in use",
        K::AddrNotAvailable => "address not available",
        K::BrokenPipe => "broken pipe",
        K::AlreadyExists => "already exists",
        K::InvalidInput => "invalid input",
        K::InvalidData => "invalid data (framing or parity)",
        K::TimedOut => "timed out",
        K::Interrupted => "interrupted",
        K::Unsupported => "unsupported",
        K::OutOfMemory => "out of memory",
        K::WriteZero => "wrote nothing",
        _ => "other error",
    }
}

//! What can go wrong on the servo bench, naming the port, servo ID, field and rate.

use crate::bus::serial::SerialError;
use dynamixel::master::BusError;

/// Errors of the servo bench.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum BenchError {
    #[error("cannot open the bus on {port}")]
    Open { port: String, source: SerialError },
    #[error("cannot change the line rate of {port} to {baud} bit/s")]
    SetBaud {
        port: String,
        baud: u32,
        source: SerialError,
    },
    #[error(
        "no servo with ID {id} answers on {port} at any MX rate ({rates}); check power and wiring"
    )]
    IdAtNoRate { port: String, id: u8, rates: String },
    #[error(
        "no servo answers on {port} at any MX rate ({rates}): check the servos' power and wiring"
    )]
    NoneAtAnyRate { port: String, rates: String },
    #[error(
        "no servo answers on {port} at {rates} bit/s: try another rate (baud {next}) or baud auto (dbot dxl --baud, Bench.open(baud=)), and check power and wiring"
    )]
    NoneAtRate {
        port: String,
        rates: String,
        next: u32,
    },
    #[error("field \"{name}\": no such control table field; known: {known}")]
    UnknownField { name: String, known: String },
    #[error("length {len}: must be 1..=147 bytes")]
    BadLength { len: u16 },
    #[error("value for {field}: can only write 1, 2 or 4 byte registers, not {size}")]
    WriteSize { field: String, size: u8 },
    #[error("value for {field}: {value} does not fit in {size} byte(s) ({min}..={max})")]
    ValueRange {
        field: String,
        value: i64,
        size: u8,
        min: i64,
        max: i64,
    },
    #[error("{what} of ID {id} on {port}")]
    Bus {
        port: String,
        id: u8,
        /// What was being done, e.g. "reading Goal Position".
        what: String,
        source: BusError,
    },
    #[error("return delay {us} us: must be even and at most 508 (register unit 2 us, max 254)")]
    ReturnDelay { us: u32 },
    #[error("new ID {id}: IDs go up to 252")]
    NewIdRange { id: u8 },
    #[error("new ID {id}: a servo with that ID already answers on {port}")]
    NewIdTaken { port: String, id: u8 },
    #[error("new baud {baud}: not a rate the MX(2.0) supports")]
    NewBaud { baud: u32 },
    /// The port cannot be a serial port (missing, a directory, a regular file, a device that is
    /// not a terminal): said before the terminal layer's "Not a typewriter".
    #[error("{message}")]
    NotSerialPort { port: String, message: String },
}

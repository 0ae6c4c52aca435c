//! The servo bench: direct access to Dynamixel servos through a USB serial adapter (U2D2) or
//! `dbot sim-bus` for setting them up — find IDs at a rate or every MX(2.0) rate (`scan`), read
//! and write registers by e-manual field name or address (`registers`), change ID, baud and
//! Return Delay Time (`setup`). `dbot dxl` and the Python `dbot.Bench` print what these return.

mod error;
pub mod rates;
pub mod registers;
pub mod scan;
pub mod serial_path;
pub mod setup;

pub use error::BenchError;
pub use rates::{BaudChoice, FACTORY_BAUD};
pub use registers::{Reading, Target, Written};
pub use scan::{Found, Pinged, Scan};
pub use setup::{SetupDone, SetupRequest};

use crate::bus::serial::{SerialMaster, block_on, open_master};

/// A bench on one serial port: the rate is fixed, or with [`BaudChoice::Auto`] found on first use
/// (by a scan, or by pinging the servo a read, write or setup addresses).
pub struct Bench {
    port: String,
    choice: BaudChoice,
    slack_us: u32,
    open: Option<(u32, SerialMaster)>,
}

impl std::fmt::Debug for Bench {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Bench")
            .field("port", &self.port)
            .field("choice", &self.choice)
            .field("baud", &self.baud())
            .finish()
    }
}

impl Bench {
    /// A bench on `port` (nothing is opened yet); `reply_slack_us` is the time allowed per reply
    /// beyond its wire time (USB adapters add latency).
    pub fn new(port: &str, choice: BaudChoice, reply_slack_us: u32) -> Self {
        Self {
            port: port.to_owned(),
            choice,
            slack_us: reply_slack_us,
            open: None,
        }
    }

    pub fn port(&self) -> &str {
        &self.port
    }

    /// The rate the bus is open at, once it is.
    pub fn baud(&self) -> Option<u32> {
        self.open.as_ref().map(|(b, _)| *b)
    }

    /// Closes the port if it is open (a later call opens it again, at the rate chosen).
    pub fn close(&mut self) {
        self.open = None;
    }

    /// Opens the bus for servo `id`: at the chosen rate, or with `auto` at the first MX rate at
    /// which `id` answers a ping. Returns the rate.
    pub fn connect(&mut self, id: u8) -> Result<u32, BenchError> {
        if let Some((b, _)) = &self.open {
            return Ok(*b);
        }
        let found = match self.choice {
            BaudChoice::Rate(b) => (b, self.open_at(b)?),
            BaudChoice::Auto => self.find_baud(id)?,
        };
        let b = found.0;
        self.open = Some(found);
        Ok(b)
    }

    fn master(&mut self, id: u8) -> Result<&mut SerialMaster, BenchError> {
        self.connect(id)?;
        Ok(&mut self.open.as_mut().expect("connected").1)
    }

    /// The bus at `baud`. A port that cannot be a serial port is refused first, saying what it
    /// is ([`serial_path::check_serial_path`]), for every door (`dbot dxl`, `dbot.Bench`).
    fn open_at(&self, baud: u32) -> Result<SerialMaster, BenchError> {
        serial_path::check_serial_path(std::path::Path::new(&self.port))?;
        open_master(&self.port, baud, self.slack_us).map_err(|source| BenchError::Open {
            port: self.port.clone(),
            source,
        })
    }

    fn find_baud(&self, id: u8) -> Result<(u32, SerialMaster), BenchError> {
        for b in BaudChoice::Auto.candidates() {
            let mut m = self.open_at(b)?;
            if block_on(m.ping(id)).is_ok() {
                return Ok((b, m));
            }
        }
        Err(BenchError::IdAtNoRate {
            port: self.port.clone(),
            id,
            rates: rates::list(&BaudChoice::Auto.candidates()),
        })
    }
}

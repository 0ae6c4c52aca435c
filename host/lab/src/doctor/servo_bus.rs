//! The servo bus the bring-up check reads registers on: a serial port (a U2D2 on the robot's bus,
//! or `dbot sim-bus`'s link) or the in-process robot's simulated wire (a second master on it, as
//! a U2D2 clipped onto the robot's bus would be), or a board that passes reads through to its bus.

use board::bus::serial::{SerialMaster, block_on, open_master};
use dynamixel::instruction::StatusError;
use dynamixel::master::{BusError, BusMaster, MasterConfig, PingReply, ReplyFault};
use dynamixel::sim::{SimMaster, SimWire};

/// Time allowed per reply beyond its wire time on a serial adapter, us (`dbot dxl`'s default:
/// a U2D2's latency timer, a servo still at the factory Return Delay Time of 500 us).
pub const SERIAL_REPLY_SLACK_US: u32 = 20_000;
/// The same on the simulated wire: covers the longest Return Delay Time (254 x 2 us = 508 us),
/// so a servo left at the factory delay still answers and is reported for it.
pub const SIM_REPLY_SLACK_US: u32 = 1_000;

/// Pings and register reads on one servo bus, at a line rate that can change.
pub trait ServoBus {
    /// Where the bus is, for messages (`/dev/ttyUSB0`, `the virtual robot's bus`).
    fn name(&self) -> String;
    /// The port to give `dbot dxl -p` to fix a servo, when there is one.
    fn dxl_port(&self) -> Option<String>;
    /// The line rate now, bit/s.
    fn baud(&self) -> u32;
    /// Changes the line rate (to look for servos set to another one).
    fn set_baud(&mut self, baud: u32) -> Result<(), String>;
    fn ping(&mut self, id: u8) -> Result<PingReply, BusError>;
    /// Reads `out.len()` bytes at `addr` of servo `id`.
    fn read(&mut self, id: u8, addr: u16, out: &mut [u8]) -> Result<StatusError, BusError>;
}

/// A bus on a serial port.
pub struct SerialBus {
    port: String,
    baud: u32,
    /// Always `Some` between calls (taken apart only to change the rate).
    master: Option<SerialMaster>,
}

impl std::fmt::Debug for SerialBus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SerialBus")
            .field("port", &self.port)
            .field("baud", &self.baud)
            .finish()
    }
}

impl SerialBus {
    /// Opens `port` at `baud`.
    pub fn open(port: &str, baud: u32) -> Result<Self, String> {
        board::bench::serial_path::check_serial_path(std::path::Path::new(port))
            .map_err(|e| e.to_string())?;
        let master = open_master(port, baud, SERIAL_REPLY_SLACK_US)
            .map_err(|e| format!("cannot open the servo bus {port}: {e}"))?;
        Ok(Self {
            port: port.to_owned(),
            baud,
            master: Some(master),
        })
    }
}

impl ServoBus for SerialBus {
    fn name(&self) -> String {
        self.port.clone()
    }
    fn dxl_port(&self) -> Option<String> {
        Some(self.port.clone())
    }
    fn baud(&self) -> u32 {
        self.baud
    }
    fn set_baud(&mut self, baud: u32) -> Result<(), String> {
        let (mut io, dir, clock) = self.master.take().expect("open").into_parts();
        let result = io.set_baud(baud).map_err(|e| e.to_string());
        if result.is_ok() {
            self.baud = baud;
        }
        self.master = Some(BusMaster::new(
            io,
            dir,
            clock,
            MasterConfig {
                baud: self.baud,
                reply_slack_us: SERIAL_REPLY_SLACK_US,
            },
        ));
        result
    }
    fn ping(&mut self, id: u8) -> Result<PingReply, BusError> {
        block_on(self.master.as_mut().expect("open").ping(id))
    }
    fn read(&mut self, id: u8, addr: u16, out: &mut [u8]) -> Result<StatusError, BusError> {
        block_on(self.master.as_mut().expect("open").read(id, addr, out))
    }
}

/// A second master on the in-process robot's simulated wire.
pub struct SimBus {
    name: String,
    wire: SimWire,
    master: SimMaster,
}

impl std::fmt::Debug for SimBus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SimBus").field("name", &self.name).finish()
    }
}

impl SimBus {
    /// A master on `wire` at the wire's rate `baud`, named `name` in messages.
    pub fn new(name: &str, wire: SimWire, baud: u32) -> Self {
        let master = wire.master(MasterConfig {
            baud,
            reply_slack_us: SIM_REPLY_SLACK_US,
        });
        Self {
            name: name.to_owned(),
            wire,
            master,
        }
    }
}

impl ServoBus for SimBus {
    fn name(&self) -> String {
        self.name.clone()
    }
    fn dxl_port(&self) -> Option<String> {
        None
    }
    fn baud(&self) -> u32 {
        self.master.config().baud
    }
    fn set_baud(&mut self, baud: u32) -> Result<(), String> {
        self.wire.set_baud(baud);
        self.master.set_config(MasterConfig {
            baud,
            reply_slack_us: SIM_REPLY_SLACK_US,
        });
        Ok(())
    }
    fn ping(&mut self, id: u8) -> Result<PingReply, BusError> {
        let wire = self.wire.clone();
        wire.block_on(self.master.ping(id))
    }
    fn read(&mut self, id: u8, addr: u16, out: &mut [u8]) -> Result<StatusError, BusError> {
        let wire = self.wire.clone();
        wire.block_on(self.master.read(id, addr, out))
    }
}

/// The servo bus behind a board: pings and reads passed through it (`ReadServo`, protocol
/// version 9), between its bus cycles. Its rate is the board's (`dbot set --baud` moves the servos
/// too), so a servo at another rate cannot be looked for through it.
pub struct BoardBus<'a, T: board::link::Transport> {
    board: &'a mut board::link::Board<T>,
    baud: u32,
}

impl<T: board::link::Transport> std::fmt::Debug for BoardBus<'_, T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BoardBus")
            .field("port", &self.board.port())
            .field("baud", &self.baud)
            .finish()
    }
}

impl<'a, T: board::link::Transport> BoardBus<'a, T> {
    /// The bus of `board`, which runs at `baud` bit/s.
    pub fn new(board: &'a mut board::link::Board<T>, baud: u32) -> Self {
        Self { board, baud }
    }

    /// One read through the board: a lost link or a read not done within 1 s of the board's
    /// clock reads as a timeout (the check then names the servo silent).
    fn pass(&mut self, read: protocol::ServoRead) -> Result<protocol::ServoReadOutcome, BusError> {
        let timeout = BusError::Reply {
            id: read.id,
            fault: ReplyFault::Timeout,
        };
        match self
            .board
            .read_servo(read, std::time::Duration::from_secs(1))
        {
            Ok(Some(o)) => Ok(o),
            Ok(None) | Err(_) => Err(timeout),
        }
    }
}

impl<T: board::link::Transport> ServoBus for BoardBus<'_, T> {
    fn name(&self) -> String {
        format!("the bus of the board on {}", self.board.port())
    }
    fn dxl_port(&self) -> Option<String> {
        None
    }
    fn baud(&self) -> u32 {
        self.baud
    }
    fn set_baud(&mut self, baud: u32) -> Result<(), String> {
        if baud == self.baud {
            return Ok(());
        }
        Err(format!(
            "the board's bus runs at {} bit/s; other rates are searched with a U2D2 (--bus PORT)",
            self.baud
        ))
    }
    fn ping(&mut self, id: u8) -> Result<PingReply, BusError> {
        use protocol::ServoReadOutcome as O;
        match self.pass(protocol::ServoRead {
            id,
            addr: 0,
            len: 0,
        })? {
            O::Ping {
                error,
                model_number,
                firmware,
            } => Ok(PingReply {
                id,
                model_number,
                firmware,
                error: StatusError(error),
            }),
            O::Timeout => Err(BusError::Reply {
                id,
                fault: ReplyFault::Timeout,
            }),
            O::Data { .. } | O::Corrupt => Err(BusError::Reply {
                id,
                fault: ReplyFault::Crc,
            }),
        }
    }
    fn read(&mut self, id: u8, addr: u16, out: &mut [u8]) -> Result<StatusError, BusError> {
        use protocol::ServoReadOutcome as O;
        let len = u8::try_from(out.len())
            .ok()
            .filter(|&n| n > 0 && usize::from(n) <= protocol::MAX_SERVO_READ)
            .ok_or(BusError::ResultsTooShort {
                servos: out.len(),
                results: protocol::MAX_SERVO_READ,
            })?;
        match self.pass(protocol::ServoRead { id, addr, len })? {
            O::Data { error, data } if data.len() == out.len() => {
                out.copy_from_slice(&data);
                Ok(StatusError(error))
            }
            O::Timeout => Err(BusError::Reply {
                id,
                fault: ReplyFault::Timeout,
            }),
            O::Data { .. } | O::Ping { .. } | O::Corrupt => Err(BusError::Reply {
                id,
                fault: ReplyFault::Crc,
            }),
        }
    }
}

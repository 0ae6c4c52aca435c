//! Setting a servo up: torque off, then Return Delay Time, ID and baud (in that order), and a
//! check that the servo answers at its new ID and rate.

use super::{Bench, BenchError};
use crate::bus::serial::block_on;
use dynamixel::control_table as ct;
use dynamixel::master::{BusError, BusMaster, MasterConfig};

/// What to change; `None` leaves it as it is.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SetupRequest {
    pub new_id: Option<u8>,
    /// bit/s, one of the MX(2.0) rates.
    pub new_baud: Option<u32>,
    /// µs, even, 0..=508 (the robot's bus wants 0).
    pub return_delay_us: Option<u32>,
}

/// What a setup did, and the servo's answer at its new ID and rate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SetupDone {
    pub old_id: u8,
    pub id: u8,
    pub baud: u32,
    pub return_delay_us: Option<u32>,
    pub new_id: Option<u8>,
    pub new_baud: Option<u32>,
    pub model_number: u16,
    pub firmware: u8,
}

impl Bench {
    /// Torque off, then sets Return Delay Time, ID and baud of servo `id` and checks that it
    /// answers as asked; the bench then talks at the new rate.
    pub fn setup(&mut self, id: u8, req: SetupRequest) -> Result<SetupDone, BenchError> {
        if let Some(us) = req.return_delay_us
            && (us > 508 || us % 2 != 0)
        {
            return Err(BenchError::ReturnDelay { us });
        }
        if let Some(n) = req.new_id
            && n > dynamixel::instruction::MAX_ID
        {
            return Err(BenchError::NewIdRange { id: n });
        }
        let code = match req.new_baud {
            Some(b) => Some(ct::baud_code(b).ok_or(BenchError::NewBaud { baud: b })?),
            None => None,
        };
        let port = self.port.clone();
        let bus = |id: u8, what: &str| {
            let (port, what) = (port.clone(), what.to_owned());
            move |source: BusError| BenchError::Bus {
                port,
                id,
                what,
                source,
            }
        };
        let m = self.master(id)?;
        block_on(m.ping(id)).map_err(bus(id, "pinging"))?;
        block_on(m.write(id, ct::TORQUE_ENABLE.addr, &[0])).map_err(bus(
            id,
            "turning torque off (EEPROM is locked while it is on)",
        ))?;
        if let Some(us) = req.return_delay_us {
            block_on(m.write(id, ct::RETURN_DELAY_TIME.addr, &[(us / 2) as u8]))
                .map_err(bus(id, "writing Return Delay Time"))?;
        }
        let mut id_now = id;
        if let Some(n) = req.new_id {
            if n != id && block_on(m.ping(n)).is_ok() {
                return Err(BenchError::NewIdTaken { port, id: n });
            }
            block_on(m.write(id, ct::ID.addr, &[n])).map_err(bus(id, "writing ID"))?;
            id_now = n;
        }
        if let (Some(b), Some(code)) = (req.new_baud, code) {
            block_on(m.write(id_now, ct::BAUD_RATE.addr, &[code]))
                .map_err(bus(id_now, "writing Baud Rate"))?;
            let (_, m) = self.open.take().expect("connected");
            let (mut io, d, c) = m.into_parts();
            io.set_baud(b).map_err(|source| BenchError::SetBaud {
                port: port.clone(),
                baud: b,
                source,
            })?;
            let config = MasterConfig {
                baud: b,
                reply_slack_us: self.slack_us,
            };
            self.open = Some((b, BusMaster::new(io, d, c, config)));
        }
        let (baud, m) = self.open.as_mut().expect("connected");
        let p = block_on(m.ping(id_now)).map_err(bus(id_now, "after setup, pinging"))?;
        Ok(SetupDone {
            old_id: id,
            id: id_now,
            baud: *baud,
            return_delay_us: req.return_delay_us,
            new_id: req.new_id,
            new_baud: req.new_baud,
            model_number: p.model_number,
            firmware: p.firmware,
        })
    }
}

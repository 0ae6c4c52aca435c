//! A chain of virtual servos on one bus, sans I/O: [`VirtualChain::handle`] takes one received
//! instruction packet and returns the replies the servos would send, each with its delay;
//! [`VirtualChain::step`] advances the motors. The simulated wire ([`super::SimWire`]) and the
//! pseudo-terminal server of `dbot sim-bus` put these on a timeline.

use super::servo::{Faults, VirtualServo};
use super::thermal::{Supply, Thermal};
use crate::control_table as ct;
use crate::encode;
use crate::instruction::{BROADCAST_ID, Instruction, StatusError};
use crate::model::ServoModel;
use crate::parser::Frame;

/// One status packet a servo sends (or would send, if it has the no-reply fault).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlannedReply {
    pub id: u8,
    /// Wait before the first byte: Return Delay Time (+ injected lateness), counted from the end
    /// of the request, or for chained replies from the end of the previous reply on the wire.
    pub delay_us: u32,
    /// The bytes; `None` when the servo stays silent (no-reply fault).
    pub bytes: Option<Vec<u8>>,
    /// Part of a Sync Read / Bulk Read / broadcast Ping: waits for the previous reply.
    pub chained: bool,
}

/// Bad use of the chain (by a test or the CLI).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ChainError {
    #[error("no virtual servo has ID {id}")]
    UnknownId { id: u8 },
    #[error("ID {id} is used twice in the chain")]
    DuplicateId { id: u8 },
    #[error("baud {baud} is not one the MX(2.0) servos support")]
    UnsupportedBaud { baud: u32 },
}

/// The servos on one bus.
#[derive(Debug, Clone, PartialEq)]
pub struct VirtualChain {
    servos: Vec<VirtualServo>,
    /// The supply all servos share (ESTIMATE, [`super::thermal`]).
    pub supply: Supply,
}

/// The servo IDs of Drosophibot II's MX-64(2.0), the six CTr joints (legs LF, LM, LH, RF, RM, RH;
/// front legs ThC1, ThC3, CTr, TrF, FTi; middle and hind legs CTr, TrF, FTi); MX-28(2.0) on the
/// rest. The robot's model file (`drosophibot2.toml`, read by `planner::model`) owns this map;
/// this crate sits below the planner and cannot read it, so this is its one copy for the crates
/// that cannot either (this crate's chains, the firmware's testkit and tests), checked equal to
/// the model file's map by host/board/tests/integration/servo_map.rs. Host code reads the model
/// (`board::robot::robot_servos`).
pub const DROSOPHIBOT_CTR_IDS: [u8; 6] = [3, 6, 9, 14, 17, 20];

impl VirtualChain {
    /// Servos `(id, model)` at factory defaults except the baud, resting at 2048 ticks.
    pub fn new(servos: &[(u8, ServoModel)], baud: u32) -> Result<Self, ChainError> {
        let code = ct::baud_code(baud).ok_or(ChainError::UnsupportedBaud { baud })?;
        let mut out: Vec<VirtualServo> = Vec::with_capacity(servos.len());
        for &(id, model) in servos {
            if out.iter().any(|s| s.id() == id) {
                return Err(ChainError::DuplicateId { id });
            }
            out.push(VirtualServo::new(id, model, code, 2048));
        }
        Ok(Self {
            servos: out,
            supply: Supply::DEFAULT,
        })
    }

    /// `n` servos with IDs 1..=n; IDs in [`DROSOPHIBOT_CTR_IDS`] are MX-64(2.0), others MX-28(2.0).
    pub fn drosophibot(n: u8, baud: u32) -> Result<Self, ChainError> {
        let list: Vec<(u8, ServoModel)> = (1..=n)
            .map(|id| {
                (
                    id,
                    if DROSOPHIBOT_CTR_IDS.contains(&id) {
                        ServoModel::Mx64
                    } else {
                        ServoModel::Mx28
                    },
                )
            })
            .collect();
        Self::new(&list, baud)
    }

    pub fn servos(&self) -> &[VirtualServo] {
        &self.servos
    }

    pub fn servos_mut(&mut self) -> &mut [VirtualServo] {
        &mut self.servos
    }

    pub fn servo(&self, id: u8) -> Option<&VirtualServo> {
        self.servos.iter().find(|s| s.id() == id)
    }

    pub fn servo_mut(&mut self, id: u8) -> Result<&mut VirtualServo, ChainError> {
        self.servos
            .iter_mut()
            .find(|s| s.id() == id)
            .ok_or(ChainError::UnknownId { id })
    }

    /// Sets the Return Delay Time register (2 us units) of every servo.
    pub fn set_return_delay_all(&mut self, code: u8) {
        for s in &mut self.servos {
            s.put(ct::RETURN_DELAY_TIME, code as u32);
        }
    }

    /// Replaces the fault set of servo `id`.
    pub fn set_faults(&mut self, id: u8, faults: Faults) -> Result<(), ChainError> {
        self.servo_mut(id)?.faults = faults;
        Ok(())
    }

    /// Latches an overload on servo `id` (torque off, Alert until Reboot).
    pub fn trigger_overload(&mut self, id: u8) -> Result<(), ChainError> {
        self.servo_mut(id)?.trigger_overload();
        Ok(())
    }

    /// External load torque on servo `id` in N m (positive toward increasing ticks).
    pub fn set_external_torque(&mut self, id: u8, torque_nm: f64) -> Result<(), ChainError> {
        self.servo_mut(id)?.external_torque_nm = torque_nm;
        Ok(())
    }

    /// Replaces the thermal body of servo `id` (a high `r_th_k_per_w` makes it heat fast).
    pub fn set_thermal(&mut self, id: u8, thermal: Thermal) -> Result<(), ChainError> {
        self.servo_mut(id)?.thermal = thermal;
        Ok(())
    }

    /// Advances every motor by `dt_s` seconds, then heats each servo at its motor current and
    /// sets every servo's input voltage from the chain's total current ([`super::thermal`]).
    pub fn step(&mut self, dt_s: f64) {
        for s in &mut self.servos {
            s.step(dt_s);
        }
        let total: f64 = self.servos.iter().map(|s| s.motor_current_a()).sum();
        let volts = self.supply.at_servos(total);
        // One exponential per time constant (every servo has the same one unless a test gives
        // it another), not one per servo: the same value either way.
        let mut memo: Option<(f64, f64)> = None;
        for s in &mut self.servos {
            let tau = s.thermal.tau_s;
            let decay = match memo {
                Some((t, d)) if t == tau => d,
                _ => {
                    let d = s.thermal.decay(dt_s);
                    memo = Some((tau, d));
                    d
                }
            };
            s.heat_decayed(decay, volts);
        }
    }

    /// Executes one instruction packet heard at `baud` (servos set to another baud do not hear
    /// it) and returns the replies in wire order.
    pub fn handle(&mut self, req: &Frame<'_>, baud: u32) -> Vec<PlannedReply> {
        let mut out = self.execute(req, baud);
        // Counted corruption: each reply a servo sends uses up one (silent servos send none).
        for r in &mut out {
            let Some(bytes) = r.bytes.as_mut() else {
                continue;
            };
            let Some(s) = self.servos.iter_mut().find(|s| s.id() == r.id) else {
                continue;
            };
            if s.faults.corrupt_next > 0 && !s.faults.corrupt_crc && bytes.len() >= 2 {
                s.faults.corrupt_next -= 1;
                let n = bytes.len();
                bytes[n - 2] ^= 0xFF;
            }
        }
        out
    }

    fn execute(&mut self, req: &Frame<'_>, baud: u32) -> Vec<PlannedReply> {
        let mut out = Vec::new();
        let p = req.params;
        let Some(inst) = Instruction::from_code(req.instruction) else {
            if req.id != BROADCAST_ID {
                self.reply_one(req.id, baud, 0, StatusError::INSTRUCTION, &[], &mut out);
            }
            return out;
        };
        match inst {
            Instruction::Ping if req.id == BROADCAST_ID => {
                let mut ids: Vec<u8> = self.listening(baud).map(|s| s.id()).collect();
                ids.sort_unstable();
                for id in ids {
                    let s = self.servo(id).unwrap();
                    let data = ping_data(s);
                    out.push(Self::status(s, 0, &data, true));
                }
            }
            Instruction::Ping => {
                if let Some(s) = self.listening(baud).find(|s| s.id() == req.id) {
                    let data = ping_data(s);
                    out.push(Self::status(s, 0, &data, false));
                }
            }
            Instruction::Read if p.len() != 4 => {
                self.reply_one(req.id, baud, 1, StatusError::DATA_LENGTH, &[], &mut out)
            }
            Instruction::Read => {
                let (addr, len) = (u16le(&p[0..2]), u16le(&p[2..4]));
                if let Some(s) = self.listening(baud).find(|s| s.id() == req.id) {
                    let r = match s.read(addr, len) {
                        Ok(d) => Self::planned_if(s, 1, 0, d, false),
                        Err(e) => Self::planned_if(s, 1, e, &[], false),
                    };
                    out.extend(r);
                }
            }
            Instruction::Write if p.len() < 3 => {
                self.reply_one(req.id, baud, 2, StatusError::DATA_LENGTH, &[], &mut out)
            }
            Instruction::Write => {
                let addr = u16le(&p[0..2]);
                for s in self.listening_mut(baud, req.id) {
                    let e = s.write(addr, &p[2..]).err().unwrap_or(0);
                    // The reply goes out under the ID the request used, even after an ID change.
                    if req.id != BROADCAST_ID && s.get(ct::STATUS_RETURN_LEVEL) >= 2 {
                        out.push(Self::status_as(s, req.id, e, &[], false));
                    }
                }
            }
            Instruction::Reboot => {
                for s in self.listening_mut(baud, req.id) {
                    if req.id != BROADCAST_ID {
                        out.extend(Self::planned_if(s, 2, 0, &[], false));
                    }
                    s.reboot();
                }
            }
            Instruction::SyncWrite if p.len() >= 4 => {
                let (addr, len) = (u16le(&p[0..2]), u16le(&p[2..4]) as usize);
                for entry in p[4..].chunks_exact(len + 1) {
                    if let Some(s) = self.listening_mut(baud, entry[0]).next() {
                        let _ = s.write(addr, &entry[1..]);
                    }
                }
            }
            Instruction::BulkWrite => {
                let mut rest = p;
                while rest.len() >= 5 {
                    let (id, addr, len) =
                        (rest[0], u16le(&rest[1..3]), u16le(&rest[3..5]) as usize);
                    let Some(data) = rest.get(5..5 + len) else {
                        break;
                    };
                    if let Some(s) = self.listening_mut(baud, id).next() {
                        let _ = s.write(addr, data);
                    }
                    rest = &rest[5 + len..];
                }
            }
            Instruction::SyncRead if p.len() >= 4 => {
                let (addr, len) = (u16le(&p[0..2]), u16le(&p[2..4]));
                for &id in &p[4..] {
                    self.read_reply(id, baud, addr, len, &mut out);
                }
            }
            Instruction::BulkRead => {
                for e in p.chunks_exact(5) {
                    self.read_reply(e[0], baud, u16le(&e[1..3]), u16le(&e[3..5]), &mut out);
                }
            }
            // Fast Sync/Bulk Read are X-series only: MX(2.0) firmware ignores them (broadcast).
            Instruction::FastSyncRead
            | Instruction::FastBulkRead
            | Instruction::SyncRead
            | Instruction::SyncWrite => {}
            // Not modelled: answered as an unknown instruction.
            _ => {
                if req.id != BROADCAST_ID {
                    self.reply_one(req.id, baud, 2, StatusError::INSTRUCTION, &[], &mut out);
                }
            }
        }
        out
    }

    fn read_reply(&self, id: u8, baud: u32, addr: u16, len: u16, out: &mut Vec<PlannedReply>) {
        if let Some(s) = self.listening(baud).find(|s| s.id() == id) {
            let r = match s.read(addr, len) {
                Ok(d) => Self::planned_if(s, 1, 0, d, true),
                Err(e) => Self::planned_if(s, 1, e, &[], true),
            };
            out.extend(r);
        }
    }

    fn listening(&self, baud: u32) -> impl Iterator<Item = &VirtualServo> {
        self.servos.iter().filter(move |s| s.baud() == Some(baud))
    }

    fn listening_mut(&mut self, baud: u32, id: u8) -> impl Iterator<Item = &mut VirtualServo> {
        self.servos
            .iter_mut()
            .filter(move |s| s.baud() == Some(baud) && (id == BROADCAST_ID || s.id() == id))
    }

    fn reply_one(
        &self,
        id: u8,
        baud: u32,
        level: u32,
        error: u8,
        data: &[u8],
        out: &mut Vec<PlannedReply>,
    ) {
        if let Some(s) = self.listening(baud).find(|s| s.id() == id) {
            out.extend(Self::planned_if(s, level, error, data, false));
        }
    }

    /// A reply if the servo's Status Return Level allows one for an instruction of `level`
    /// (0: only Ping, 1: also reads, 2: everything).
    fn planned_if(
        s: &VirtualServo,
        level: u32,
        error: u8,
        data: &[u8],
        chained: bool,
    ) -> Option<PlannedReply> {
        if s.get(ct::STATUS_RETURN_LEVEL) < level {
            return None;
        }
        Some(Self::status(s, error, data, chained))
    }

    fn status(s: &VirtualServo, error: u8, data: &[u8], chained: bool) -> PlannedReply {
        Self::status_as(s, s.id(), error, data, chained)
    }

    fn status_as(s: &VirtualServo, id: u8, error: u8, data: &[u8], chained: bool) -> PlannedReply {
        let mut buf = vec![0u8; 16 + data.len() * 2];
        // Cannot fail: the buffer has room for the worst-case stuffing.
        let n = encode::status(&mut buf, id, error | s.alert(), data).unwrap_or(0);
        buf.truncate(n);
        if s.faults.corrupt_crc && n > 0 {
            buf[n - 2] ^= 0xFF;
        }
        PlannedReply {
            id,
            delay_us: s.reply_delay_us(),
            bytes: (!s.faults.no_reply).then_some(buf),
            chained,
        }
    }
}

fn ping_data(s: &VirtualServo) -> [u8; 3] {
    let m = s.model().number().to_le_bytes();
    [m[0], m[1], s.get(ct::FIRMWARE_VERSION) as u8]
}

fn u16le(b: &[u8]) -> u16 {
    u16::from_le_bytes([b[0], b[1]])
}

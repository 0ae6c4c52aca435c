//! Setup helpers of the bus master: Ping, Read, Write, Reboot, generic Sync/Bulk Read and Write.

use super::schedule::{Ledger, Schedule, SlotData, Step};
use super::{
    BusError, BusMaster, Clock, DirectionPin, MAX_SERVOS, PingReply, ReplyFault, check_count,
};
use crate::encode;
use crate::instruction::{BROADCAST_ID, STATUS, StatusError};
use crate::parser::{Frame, FrameError};
use embedded_io_async::{Read, ReadReady, Write};

/// Per-servo outcome of a generic Sync/Bulk Read: the status error byte (maybe with Alert) or a fault.
pub type ReadOutcome = Result<StatusError, ReplyFault>;

impl<IO: Read + ReadReady + Write, D: DirectionPin, C: Clock> BusMaster<IO, D, C> {
    /// Sends the request in the buffer and waits for `id`'s status; copies its data into `out`.
    /// Returns the error byte (Alert allowed) and the data length.
    async fn transact(
        &mut self,
        len: usize,
        id: u8,
        out: &mut [u8],
    ) -> Result<(StatusError, usize), BusError> {
        self.send(len).await?;
        let schedule = Schedule {
            data: SlotData::Uniform {
                slots: 1,
                data: out.len(),
            },
            config: self.config,
        };
        let mut result: Option<Result<(StatusError, usize), ReplyFault>> = None;
        let mut on_frame = |ev: Result<Frame<'_>, FrameError>| -> Step {
            match ev {
                Ok(f) if f.instruction != STATUS || f.id != id => Step::Ignore,
                Ok(f) => {
                    result = Some(match f.status() {
                        None => Err(ReplyFault::Malformed),
                        Some(s) if s.error.number().is_some() => Err(ReplyFault::Status(s.error)),
                        Some(s) if s.data.len() > out.len() => Err(ReplyFault::Malformed),
                        Some(s) => {
                            out[..s.data.len()].copy_from_slice(s.data);
                            Ok((s.error, s.data.len()))
                        }
                    });
                    Step::Done
                }
                Err(FrameError::Crc { id: got, .. }) if got == id => {
                    result = Some(Err(ReplyFault::Crc));
                    Step::Done
                }
                Err(_) => Step::Ignore,
            }
        };
        self.receive(&schedule, &mut on_frame).await?;
        match result {
            Some(Ok(r)) => Ok(r),
            Some(Err(fault)) => Err(BusError::Reply { id, fault }),
            None => Err(BusError::Reply {
                id,
                fault: ReplyFault::Timeout,
            }),
        }
    }

    /// Ping one servo: its model number and firmware version.
    pub async fn ping(&mut self, id: u8) -> Result<PingReply, BusError> {
        let n = encode::ping(&mut self.tx, id)?;
        let mut data = [0u8; 3];
        let (error, len) = self.transact(n, id, &mut data).await?;
        if len != 3 {
            return Err(BusError::DataLength {
                id,
                expected: 3,
                got: len,
            });
        }
        Ok(PingReply {
            id,
            model_number: u16::from_le_bytes([data[0], data[1]]),
            firmware: data[2],
            error,
        })
    }

    /// Reads `out.len()` bytes at `addr` of servo `id`.
    pub async fn read(
        &mut self,
        id: u8,
        addr: u16,
        out: &mut [u8],
    ) -> Result<StatusError, BusError> {
        let n = encode::read(&mut self.tx, id, addr, out.len() as u16)?;
        let expected = out.len();
        let (error, len) = self.transact(n, id, out).await?;
        if len != expected {
            return Err(BusError::DataLength {
                id,
                expected,
                got: len,
            });
        }
        Ok(error)
    }

    /// Writes `data` at `addr` of servo `id` and waits for its status (no wait for broadcast).
    pub async fn write(&mut self, id: u8, addr: u16, data: &[u8]) -> Result<StatusError, BusError> {
        let n = encode::write(&mut self.tx, id, addr, data)?;
        if id == BROADCAST_ID {
            self.send(n).await?;
            return Ok(StatusError(0));
        }
        Ok(self.transact(n, id, &mut []).await?.0)
    }

    /// Reboots servo `id` (clears a latched hardware error; torque comes back off).
    pub async fn reboot(&mut self, id: u8) -> Result<StatusError, BusError> {
        let n = encode::reboot(&mut self.tx, id)?;
        Ok(self.transact(n, id, &mut []).await?.0)
    }

    /// Sync Write `len` bytes at `addr` to each `(id, data)`; no replies.
    pub async fn sync_write<'d>(
        &mut self,
        addr: u16,
        len: u16,
        entries: impl IntoIterator<Item = (u8, &'d [u8])>,
    ) -> Result<(), BusError> {
        let n = encode::sync_write(&mut self.tx, addr, len, entries)?;
        self.send(n).await
    }

    /// Bulk Write `(id, addr, data)` entries; no replies.
    pub async fn bulk_write<'d>(
        &mut self,
        entries: impl IntoIterator<Item = (u8, u16, &'d [u8])>,
    ) -> Result<(), BusError> {
        let n = encode::bulk_write(&mut self.tx, entries)?;
        self.send(n).await
    }

    /// Sync Read `len` bytes at `addr` of each of `ids`: servo `ids[i]`'s data lands in
    /// `data[i*len..(i+1)*len]`, its outcome in `outcomes[i]`.
    pub async fn sync_read(
        &mut self,
        addr: u16,
        len: u16,
        ids: &[u8],
        data: &mut [u8],
        outcomes: &mut [ReadOutcome],
    ) -> Result<(), BusError> {
        check_count(ids.len())?;
        let n = encode::sync_read(&mut self.tx, addr, len, ids)?;
        let mut lens = [0u16; MAX_SERVOS];
        lens[..ids.len().min(MAX_SERVOS)].fill(len);
        self.collect_reads(n, ids, &lens, data, outcomes).await
    }

    /// Bulk Read `(id, addr, len)` entries: data of entry i follows that of entry i-1 in `data`.
    pub async fn bulk_read(
        &mut self,
        entries: &[(u8, u16, u16)],
        data: &mut [u8],
        outcomes: &mut [ReadOutcome],
    ) -> Result<(), BusError> {
        check_count(entries.len())?;
        let n = encode::bulk_read(&mut self.tx, entries)?;
        let mut ids = [0u8; MAX_SERVOS];
        let mut lens = [0u16; MAX_SERVOS];
        for (i, &(id, _, len)) in entries.iter().take(MAX_SERVOS).enumerate() {
            ids[i] = id;
            lens[i] = len;
        }
        let k = entries.len().min(MAX_SERVOS);
        self.collect_reads(n, &ids[..k], &lens[..k], data, outcomes)
            .await
    }

    async fn collect_reads(
        &mut self,
        n: usize,
        ids: &[u8],
        lens: &[u16],
        data: &mut [u8],
        outcomes: &mut [ReadOutcome],
    ) -> Result<(), BusError> {
        let total: usize = lens[..ids.len()].iter().map(|&l| l as usize).sum();
        if outcomes.len() < ids.len() || data.len() < total {
            return Err(BusError::ResultsTooShort {
                servos: ids.len(),
                results: outcomes.len().min(data.len()),
            });
        }
        self.send(n).await?;
        outcomes[..ids.len()].fill(Err(ReplyFault::Timeout));
        let mut ledger = Ledger::new(ids);
        let schedule = Schedule {
            data: SlotData::PerSlot(&lens[..ids.len()]),
            config: self.config,
        };
        let mut on_frame = |ev: Result<Frame<'_>, FrameError>| -> Step {
            let (id, st) = match ev {
                Ok(f) if f.instruction != STATUS => return Step::Ignore,
                Ok(f) => (f.id, f.status().ok_or(ReplyFault::Malformed)),
                Err(e) => return ledger.garbled(&e, outcomes),
            };
            let Some(i) = ledger.open_slot(id) else {
                return Step::Ignore;
            };
            let offset: usize = lens[..i].iter().map(|&l| l as usize).sum();
            outcomes[i] = st.and_then(|s| {
                if s.error.number().is_some() {
                    Err(ReplyFault::Status(s.error))
                } else if s.data.len() != lens[i] as usize {
                    Err(ReplyFault::Malformed)
                } else {
                    data[offset..offset + s.data.len()].copy_from_slice(s.data);
                    Ok(s.error)
                }
            });
            ledger.settle(i)
        };
        if !ids.is_empty() {
            self.receive(&schedule, &mut on_frame).await?;
        }
        Ok(())
    }
}

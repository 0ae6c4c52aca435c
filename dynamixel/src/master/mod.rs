//! Async bus master over `embedded_io_async::{Read, Write}`, a [`DirectionPin`] and a [`Clock`].
//!
//! One bus cycle ([`BusMaster::cycle`]) sends a Sync Write of goal positions and a Sync Read of
//! 126..=135 back to back, then collects one status per servo. The replies follow a schedule
//! ([`schedule`]): each expected reply is due one reply budget after the previous one, so a
//! missing, late, corrupt or noise-garbled reply is reported for that servo alone and the others
//! are still collected. Instruction packets on the wire (the master's own echo when TX and RX
//! share it) are skipped.

mod hal;
mod schedule;
mod single;
mod types;

pub use hal::{AutoDirection, Clock, DirectionPin, with_deadline};
pub use types::*;

use crate::control_table::{FEEDBACK_ADDR, FEEDBACK_LEN, GOAL_POSITION};
use crate::encode;
use crate::parser::{Frame, FrameError, Parser};
use embedded_io_async::{Error as _, Read, ReadReady, Write};
use schedule::{Ledger, Progress, Schedule, SlotData, Step, Timeout};

/// Request buffer size: a 22-servo cycle needs 160 bytes (more if stuffed).
pub const TX_CAPACITY: usize = 512;
/// Maximum number of servos in one cycle.
pub const MAX_SERVOS: usize = 64;

/// The bus master. `IO` is the UART (or [`crate::sim::SimWire`]), `D` the direction pin, `C` the clock.
#[derive(Debug)]
pub struct BusMaster<IO, D, C> {
    io: IO,
    dir: D,
    clock: C,
    config: MasterConfig,
    parser: Parser,
    tx: [u8; TX_CAPACITY],
    stale_bytes: u32,
}

impl<IO: Read + ReadReady + Write, D: DirectionPin, C: Clock> BusMaster<IO, D, C> {
    pub fn new(io: IO, dir: D, clock: C, config: MasterConfig) -> Self {
        Self {
            io,
            dir,
            clock,
            config,
            parser: Parser::new(),
            tx: [0; TX_CAPACITY],
            stale_bytes: 0,
        }
    }

    pub fn config(&self) -> &MasterConfig {
        &self.config
    }

    /// Changes the timing (e.g. after switching the servos' and the UART's baud).
    pub fn set_config(&mut self, config: MasterConfig) {
        self.config = config;
    }

    pub fn clock(&self) -> &C {
        &self.clock
    }

    /// Gives back the parts.
    pub fn into_parts(self) -> (IO, D, C) {
        (self.io, self.dir, self.clock)
    }

    /// One bus cycle: Sync Write of each goal to Goal Position (116), then Sync Read of 126..=135
    /// of the same servos. `replies[i]` receives servo `goals[i]`'s feedback or fault.
    pub async fn cycle(
        &mut self,
        goals: &[Goal],
        replies: &mut [Reply],
    ) -> Result<CycleStats, BusError> {
        check_replies(goals.len(), replies.len())?;
        let mut ids = [0u8; MAX_SERVOS];
        for (slot, g) in ids.iter_mut().zip(goals) {
            *slot = g.id;
        }
        let ids = &ids[..goals.len()];
        let n = encode::sync_write_u32(
            &mut self.tx,
            GOAL_POSITION.addr,
            goals.iter().map(|g| (g.id, g.position as u32)),
        )?;
        let m = encode::sync_read(&mut self.tx[n..], FEEDBACK_ADDR, FEEDBACK_LEN, ids)?;
        let mut stats = CycleStats {
            start_us: self.clock.now_us(),
            ..Default::default()
        };
        let skipped_before = self.parser.skipped_bytes();
        let stale_before = self.stale_bytes;
        self.send(n + m).await?;
        stats.stale_bytes = self.stale_bytes.wrapping_sub(stale_before);
        stats.tx_end_us = self.clock.now_us();
        self.collect_feedback(ids, &mut replies[..ids.len()], &mut stats)
            .await?;
        stats.end_us = self.clock.now_us();
        stats.garbage_bytes = self.parser.skipped_bytes().wrapping_sub(skipped_before);
        Ok(stats)
    }

    /// Sync Read of 126..=135 only (no goals), e.g. to read the pose before torque-on.
    pub async fn read_feedback(
        &mut self,
        ids: &[u8],
        replies: &mut [Reply],
    ) -> Result<CycleStats, BusError> {
        check_replies(ids.len(), replies.len())?;
        let n = encode::sync_read(&mut self.tx, FEEDBACK_ADDR, FEEDBACK_LEN, ids)?;
        let mut stats = CycleStats {
            start_us: self.clock.now_us(),
            ..Default::default()
        };
        self.send(n).await?;
        stats.tx_end_us = self.clock.now_us();
        self.collect_feedback(ids, &mut replies[..ids.len()], &mut stats)
            .await?;
        stats.end_us = self.clock.now_us();
        Ok(stats)
    }

    async fn collect_feedback(
        &mut self,
        ids: &[u8],
        replies: &mut [Reply],
        stats: &mut CycleStats,
    ) -> Result<(), BusError> {
        replies.fill(Err(ReplyFault::Timeout));
        let mut ledger = Ledger::new(ids);
        let schedule = Schedule {
            data: SlotData::Uniform {
                slots: ids.len(),
                data: FEEDBACK_LEN as usize,
            },
            config: self.config,
        };
        let mut on_frame = |ev: Result<Frame<'_>, FrameError>| -> Step {
            let (id, outcome) = match ev {
                Ok(frame) => match frame.status() {
                    None if frame.instruction != crate::instruction::STATUS => {
                        stats.echo_frames = stats.echo_frames.saturating_add(1);
                        return Step::Ignore;
                    }
                    None => (frame.id, Err(ReplyFault::Malformed)),
                    Some(s) => (s.id, decode_feedback(s.error, s.data)),
                },
                Err(e) => return ledger.garbled(&e, replies),
            };
            let Some(i) = ledger.open_slot(id) else {
                stats.stray_frames = stats.stray_frames.saturating_add(1);
                return Step::Ignore;
            };
            replies[i] = outcome;
            ledger.settle(i)
        };
        if !ids.is_empty() {
            self.receive(&schedule, &mut on_frame).await?;
        }
        for r in replies.iter() {
            match r {
                Ok(f) if f.alert => stats.alerts += 1,
                Ok(_) => {}
                Err(ReplyFault::Timeout) => stats.timeouts += 1,
                Err(ReplyFault::Crc) => stats.crc_errors += 1,
                Err(ReplyFault::Malformed) => stats.malformed += 1,
                Err(ReplyFault::Status(_)) => stats.status_errors += 1,
            }
            if r.is_ok() {
                stats.ok += 1;
            }
        }
        Ok(())
    }

    /// Writes `len` bytes of the request buffer with the direction pin driven.
    async fn send(&mut self, len: usize) -> Result<(), BusError> {
        // Leftovers of an earlier exchange (a late reply) must not be taken for this one's replies.
        self.parser.reset();
        let mut scratch = [0u8; 32];
        while self.io.read_ready().map_err(|e| BusError::Io(e.kind()))? {
            let n = self
                .io
                .read(&mut scratch)
                .await
                .map_err(|e| BusError::Io(e.kind()))?;
            self.stale_bytes = self.stale_bytes.wrapping_add(n as u32);
        }
        self.dir.drive();
        let res = async {
            self.io.write_all(&self.tx[..len]).await?;
            self.io.flush().await
        }
        .await;
        self.dir.release_after_tx().await;
        res.map_err(|e| BusError::Io(e.kind()))
    }

    /// Feeds received bytes to `on_frame` until it says `Done`, the last slot of `schedule` has
    /// been heard, or the schedule is over ([`Progress`]). When a slot's time is over while the
    /// parser holds more bytes than any expected reply can have, the front is a false header
    /// (noise) swallowing the replies behind it: it is abandoned there and then, so those replies
    /// count and move the schedule on. At the end, any half-received packet is abandoned the same
    /// way so that complete packets behind a false header still count.
    async fn receive(
        &mut self,
        schedule: &Schedule<'_>,
        on_frame: &mut impl FnMut(Result<Frame<'_>, FrameError>) -> Step,
    ) -> Result<(), BusError> {
        let mut progress = Progress::new(self.clock.now_us());
        let max_packet = schedule.max_packet();
        let mut chunk = [0u8; 32];
        loop {
            let deadline = progress.deadline_us(schedule);
            let read = with_deadline(&self.clock, deadline, self.io.read(&mut chunk)).await;
            let now = self.clock.now_us();
            let n = match read {
                Some(Ok(n)) => n,
                Some(Err(e)) => return Err(BusError::Io(e.kind())),
                None => {
                    let end = progress.on_timeout(schedule, now) == Timeout::End;
                    let limit = if end { 0 } else { max_packet };
                    while self.parser.buffered() > limit {
                        self.parser.abandon_partial();
                        if drain(&mut self.parser, on_frame, &mut progress, now) {
                            return Ok(());
                        }
                    }
                    if end || progress.finished(schedule) {
                        return Ok(());
                    }
                    continue;
                }
            };
            progress.last_rx_us = now;
            let mut data = &chunk[..n];
            while !data.is_empty() {
                let taken = self.parser.feed(data);
                data = &data[taken..];
                if drain(&mut self.parser, on_frame, &mut progress, now) {
                    return Ok(());
                }
            }
            if progress.finished(schedule) {
                return Ok(());
            }
        }
    }
}

/// Requests for more than [`MAX_SERVOS`] servos are refused (fixed-size bookkeeping, no alloc).
/// [`check_count`], and room for each servo's reply among `results`.
fn check_replies(servos: usize, results: usize) -> Result<(), BusError> {
    check_count(servos)?;
    if results < servos {
        return Err(BusError::ResultsTooShort { servos, results });
    }
    Ok(())
}

pub(crate) fn check_count(servos: usize) -> Result<(), BusError> {
    if servos > MAX_SERVOS {
        return Err(BusError::TooManyServos {
            servos,
            max: MAX_SERVOS,
        });
    }
    Ok(())
}

/// Hands every complete frame to `on_frame` and follows the schedule; true when `on_frame` says
/// everything has arrived.
fn drain(
    parser: &mut Parser,
    on_frame: &mut impl FnMut(Result<Frame<'_>, FrameError>) -> Step,
    progress: &mut Progress,
    now_us: u64,
) -> bool {
    while let Some(ev) = parser.next_frame() {
        match on_frame(ev) {
            Step::Ignore => {}
            Step::Slot(k) => progress.heard(k, now_us),
            Step::Garbled(k) if k == progress.next => progress.heard(k, now_us),
            Step::Garbled(_) => {}
            Step::Done => return true,
        }
    }
    false
}

/// Feedback from a status packet's error byte and data, or the fault it shows.
fn decode_feedback(error: crate::instruction::StatusError, data: &[u8]) -> Reply {
    if error.number().is_some() {
        return Err(ReplyFault::Status(error));
    }
    let bytes: &[u8; 10] = data.try_into().map_err(|_| ReplyFault::Malformed)?;
    Ok(Feedback::from_bytes(bytes, error.alert()))
}

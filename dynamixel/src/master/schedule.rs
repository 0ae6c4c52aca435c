//! The reply schedule of a read: which expected status packet ("slot") is due by when, and the
//! ledger of which slots have been answered.
//!
//! In a Sync Read or Bulk Read the servos answer one after the other, in the order of the request,
//! each starting within its Return Delay Time after the previous reply has ended. Slot `k` takes
//! at most its wire time plus the reply slack, so counting from the last reply that was heard, the
//! remaining slots are due one budget after the other. Garbage on the wire (noise, a reply garbled
//! on the way) then costs only the slots it overlaps: the replies behind it are still inside
//! their own time. See [`super::BusMaster`]'s `receive` for how the schedule is followed.

use super::{MAX_SERVOS, MasterConfig, ReplyFault};
use crate::parser::FrameError;

/// Per-slot data lengths of one read.
#[derive(Debug, Clone, Copy)]
pub(super) enum SlotData<'a> {
    /// `slots` replies of `data` bytes each (Sync Read, one reply of a single transaction).
    Uniform { slots: usize, data: usize },
    /// One reply per entry, of that many data bytes (Bulk Read).
    PerSlot(&'a [u16]),
}

/// The expected replies of one read with the master's timing.
#[derive(Debug, Clone, Copy)]
pub(super) struct Schedule<'a> {
    pub data: SlotData<'a>,
    pub config: MasterConfig,
}

/// Bytes of a status packet around its data: header 4, ID, LEN 2, INST, ERR, CRC 2.
const STATUS_OVERHEAD: usize = 11;

impl Schedule<'_> {
    pub fn slots(&self) -> usize {
        match self.data {
            SlotData::Uniform { slots, .. } => slots,
            SlotData::PerSlot(lens) => lens.len(),
        }
    }

    fn data_len(&self, slot: usize) -> usize {
        match self.data {
            SlotData::Uniform { data, .. } => data,
            SlotData::PerSlot(lens) => lens.get(slot).copied().unwrap_or(0) as usize,
        }
    }

    /// Time slot `slot` may take from the end of the previous reply (or of the request): its
    /// unstuffed wire time plus the slack (Return Delay Time, turnaround; the slack also covers
    /// the rare stuffing byte, 10 us at 1 Mbit/s).
    pub fn budget_us(&self, slot: usize) -> u64 {
        let wire = self
            .config
            .wire_time_us(STATUS_OVERHEAD + self.data_len(slot));
        u64::from(self.config.reply_slack_us) + u64::from(wire)
    }

    /// The most bytes a genuine reply still being received can occupy in the parser: its length
    /// with the worst-case stuffing (one extra byte per `FF FF FD` among INST, ERR and data: at
    /// most (data + 2) / 3 of them, rounded down, which is data / 3 rounded up).
    /// More bytes buffered without a complete frame means the front is a false header.
    pub fn max_packet(&self) -> usize {
        let longest = (0..self.slots())
            .map(|k| self.data_len(k))
            .max()
            .unwrap_or(0);
        STATUS_OVERHEAD + longest + longest.div_ceil(3)
    }
}

/// What the receive loop's frame handler says about a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Step {
    /// Not a reply of this read (echo, stray, a garbled packet of an ID not expected next).
    Ignore,
    /// A valid reply filled slot `k` (0-based, wire order): the schedule continues after it.
    Slot(usize),
    /// A packet under slot `k`'s ID failed its check. Taken as that slot's (garbled) reply only
    /// when `k` is the slot due next, since the ID byte of noise is arbitrary.
    Garbled(usize),
    /// Everything expected has arrived.
    Done,
}

/// Which slots of a read have been answered by a valid packet.
#[derive(Debug)]
pub(super) struct Ledger<'a> {
    ids: &'a [u8],
    settled: [bool; MAX_SERVOS],
    remaining: usize,
}

impl<'a> Ledger<'a> {
    /// `ids` in wire order; at most [`MAX_SERVOS`] (checked by the callers).
    pub fn new(ids: &'a [u8]) -> Self {
        Self {
            ids,
            settled: [false; MAX_SERVOS],
            remaining: ids.len().min(MAX_SERVOS),
        }
    }

    /// The first slot of `id` not yet answered by a valid packet.
    pub fn open_slot(&self, id: u8) -> Option<usize> {
        self.ids
            .iter()
            .zip(&self.settled)
            .position(|(&x, &done)| x == id && !done)
    }

    /// A packet that failed its check proves nothing about its ID (noise, a false header): its
    /// fault is noted in the open slot of the ID it carries, which stays open for a valid reply.
    pub fn garbled<T>(&self, e: &FrameError, out: &mut [Result<T, ReplyFault>]) -> Step {
        let fault = match e {
            FrameError::Crc { .. } => ReplyFault::Crc,
            _ => ReplyFault::Malformed,
        };
        match self.open_slot(e.id()) {
            Some(i) => {
                out[i] = Err(fault);
                Step::Garbled(i)
            }
            None => Step::Ignore,
        }
    }

    /// Marks `slot` answered: [`Step::Done`] when it was the last one open.
    pub fn settle(&mut self, slot: usize) -> Step {
        if !self.settled[slot] {
            self.settled[slot] = true;
            self.remaining -= 1;
        }
        if self.remaining == 0 {
            Step::Done
        } else {
            Step::Slot(slot)
        }
    }
}

/// Where the receive loop is in the schedule.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Progress {
    /// The slot due next: all before it have been heard or their time is over.
    pub next: usize,
    /// When the slot before `next` ended (or the request, or that slot's time ran out).
    pub since_us: u64,
    /// When the last byte of any kind arrived.
    pub last_rx_us: u64,
}

/// What the deadline of [`Progress::deadline_us`] means once it has passed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Timeout {
    /// Slot `next` is over; the schedule goes on with the slot after it.
    SlotOver,
    /// Nothing arrived for a whole slot (or the last slot is over): the read ends.
    End,
}

impl Progress {
    pub fn new(now_us: u64) -> Self {
        Self {
            next: 0,
            since_us: now_us,
            last_rx_us: now_us,
        }
    }

    /// A frame of slot `slot` (valid, or garbled under the ID due next) ended at `now_us`.
    pub fn heard(&mut self, slot: usize, now_us: u64) {
        if slot + 1 >= self.next {
            self.next = slot + 1;
            self.since_us = self.since_us.max(now_us);
        }
    }

    /// True once the last slot has been heard or its time is over.
    pub fn finished(&self, schedule: &Schedule<'_>) -> bool {
        self.next >= schedule.slots()
    }

    /// The next moment something must be decided: the end of slot `next`'s time, or earlier if
    /// the line has been quiet since its last byte for as long as that slot may take. A quiet line
    /// ends the read: in a Sync Read every servo starts within its Return Delay Time after the
    /// previous reply (a silent servo sends nothing and takes no time), so when nothing has come
    /// for a whole slot, no servo is talking and none will.
    pub fn deadline_us(&self, schedule: &Schedule<'_>) -> u64 {
        self.since_us.min(self.last_rx_us) + schedule.budget_us(self.next)
    }

    /// Called when [`Self::deadline_us`] has passed at `now_us`.
    pub fn on_timeout(&mut self, schedule: &Schedule<'_>, now_us: u64) -> Timeout {
        let budget = schedule.budget_us(self.next);
        if now_us >= self.last_rx_us + budget {
            return Timeout::End;
        }
        self.since_us += budget;
        self.next += 1;
        if self.finished(schedule) {
            Timeout::End
        } else {
            Timeout::SlotOver
        }
    }
}

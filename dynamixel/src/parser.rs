//! Streaming packet parser: takes bytes in any chunking, finds the header, checks LEN and CRC,
//! unstuffs, and resynchronises on the next header after garbage or a bad packet.
//!
//! Usage: `feed` bytes, then call `next_frame` until it returns `None`; feed the rest, repeat. A frame
//! borrows the parser's buffer until the next call. Instruction packets (the master's own echo
//! on a shared wire, or the requests a virtual servo hears) and status packets are both
//! returned; the bus master skips the ones that are not status packets.

use crate::crc;
use crate::encode::{HEADER, PRE_INST};
use crate::instruction::{STATUS, StatusError};

/// Default buffer size: fits a status packet with 240 data bytes.
pub const DEFAULT_CAPACITY: usize = 256;

/// One packet with its parameters unstuffed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Frame<'a> {
    pub id: u8,
    pub instruction: u8,
    /// Parameters after INST, unstuffed (for a status packet the first is the error byte).
    pub params: &'a [u8],
}

/// A status packet: the servo's reply.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Status<'a> {
    pub id: u8,
    pub error: StatusError,
    pub data: &'a [u8],
}

impl<'a> Frame<'a> {
    /// The status view of this frame, `None` for instruction packets or a status without ERR.
    pub fn status(&self) -> Option<Status<'a>> {
        if self.instruction != STATUS {
            return None;
        }
        let (&error, data) = self.params.split_first()?;
        Some(Status {
            id: self.id,
            error: StatusError(error),
            data,
        })
    }
}

/// A packet that was found and rejected; the parser has already moved past its first byte.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum FrameError {
    /// The CRC does not match: `id` is as received and may itself be corrupt.
    Crc {
        id: u8,
        received: u16,
        computed: u16,
    },
    /// LEN is below the minimum of 3 or the packet would not fit the parser's buffer.
    Length {
        id: u8,
        length: u16,
        capacity: usize,
    },
}

impl FrameError {
    /// The (unverified) ID of the rejected packet.
    pub fn id(&self) -> u8 {
        match *self {
            FrameError::Crc { id, .. } | FrameError::Length { id, .. } => id,
        }
    }
}

/// The streaming parser, buffering at most `N` bytes (the largest packet it accepts).
#[derive(Debug, Clone)]
pub struct Parser<const N: usize = DEFAULT_CAPACITY> {
    buf: [u8; N],
    len: usize,
    // Bytes of the last returned frame, dropped at the next call.
    consumed: usize,
    skipped: u32,
}

impl<const N: usize> Default for Parser<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> Parser<N> {
    pub const fn new() -> Self {
        Self {
            buf: [0; N],
            len: 0,
            consumed: 0,
            skipped: 0,
        }
    }

    /// Forgets everything buffered.
    pub fn reset(&mut self) {
        self.len = 0;
        self.consumed = 0;
    }

    /// Bytes dropped so far as not belonging to any packet (garbage, rejected packets' first bytes).
    pub fn skipped_bytes(&self) -> u32 {
        self.skipped
    }

    /// Bytes buffered and not yet returned as a frame.
    pub fn buffered(&self) -> usize {
        self.len - self.consumed
    }

    /// Copies as many of `data` as fit; returns how many were taken. Call `next_frame` until `None`
    /// before feeding again when not everything was taken.
    pub fn feed(&mut self, data: &[u8]) -> usize {
        self.compact();
        let n = data.len().min(N - self.len);
        self.buf[self.len..self.len + n].copy_from_slice(&data[..n]);
        self.len += n;
        n
    }

    /// Whether [`Self::next_frame`] would surely return `None` and change nothing now: what is
    /// buffered is a header, or a prefix of one, or the start of one packet with a valid LEN
    /// whose last byte has not come yet. A caller that feeds byte by byte (a simulated servo
    /// hearing the wire) skips the call while this holds; the frames and errors it gets are the
    /// same, found at the same byte.
    pub fn awaiting_rest(&self) -> bool {
        let b = &self.buf[self.consumed..self.len];
        if b.is_empty() || !b.iter().zip(HEADER).all(|(a, h)| *a == h) {
            return false;
        }
        if b.len() < PRE_INST {
            return true;
        }
        Self::front_total(b).is_some_and(|total| b.len() < total)
    }

    /// How many more bytes can be fed before [`Self::next_frame`] could return anything: while
    /// the buffer holds the start of one packet with a valid LEN, the bytes before its last
    /// (0 otherwise, also while only a header or a prefix of one is buffered). A caller that
    /// feeds byte by byte (a simulated servo) may take that many at once without asking; the
    /// frames and errors it gets are the same, found at the same byte.
    pub fn quiet_bytes(&self) -> usize {
        let b = &self.buf[self.consumed..self.len];
        Self::front_total(b).map_or(0, |total| total.saturating_sub(b.len() + 1))
    }

    /// The whole length of the packet `b` starts with, when its header and a valid LEN (at
    /// least 3, the packet fitting the buffer) are there.
    fn front_total(b: &[u8]) -> Option<usize> {
        if b.len() < PRE_INST || b[..HEADER.len()] != HEADER {
            return None;
        }
        let length = u16::from_le_bytes([b[5], b[6]]);
        let total = PRE_INST + length as usize;
        (length >= 3 && total <= N).then_some(total)
    }

    /// Feeds one byte (as `feed(&[byte])`, without the slice copy); false when the buffer is full.
    pub fn push(&mut self, byte: u8) -> bool {
        self.compact();
        if self.len == N {
            return false;
        }
        self.buf[self.len] = byte;
        self.len += 1;
        true
    }

    /// Gives up on an incomplete packet at the front (after a timeout): drops its first byte so
    /// that packets hidden behind a false header are found by the next `next_frame`.
    pub fn abandon_partial(&mut self) {
        self.compact();
        if self.len > 0 {
            self.drop_front(1);
        }
    }

    /// The next complete frame or rejected packet in the buffer, `None` when more bytes are needed.
    pub fn next_frame(&mut self) -> Option<Result<Frame<'_>, FrameError>> {
        self.compact();
        self.sync();
        if self.len < PRE_INST {
            return None;
        }
        let id = self.buf[4];
        let length = u16::from_le_bytes([self.buf[5], self.buf[6]]);
        let total = PRE_INST + length as usize;
        if length < 3 || total > N {
            self.drop_front(1);
            return Some(Err(FrameError::Length {
                id,
                length,
                capacity: N,
            }));
        }
        if self.len < total {
            return None;
        }
        let received = u16::from_le_bytes([self.buf[total - 2], self.buf[total - 1]]);
        let computed = crc::crc16(&self.buf[..total - 2]);
        if received != computed {
            self.drop_front(1);
            return Some(Err(FrameError::Crc {
                id,
                received,
                computed,
            }));
        }
        let end = unstuff(&mut self.buf[PRE_INST..total - 2]) + PRE_INST;
        self.consumed = total;
        Some(Ok(Frame {
            id,
            instruction: self.buf[PRE_INST],
            params: &self.buf[PRE_INST + 1..end],
        }))
    }

    fn compact(&mut self) {
        if self.consumed > 0 {
            let c = self.consumed;
            self.consumed = 0;
            self.buf.copy_within(c..self.len, 0);
            self.len -= c;
        }
    }

    fn drop_front(&mut self, n: usize) {
        self.buf.copy_within(n..self.len, 0);
        self.len -= n;
        self.skipped += n as u32;
    }

    /// Drops bytes until the buffer starts with the header or a prefix of it.
    fn sync(&mut self) {
        let mut start = 0;
        while start < self.len {
            let rest = &self.buf[start..self.len];
            // Byte by byte: a slice comparison calls `memcmp` for these few bytes, and this runs
            // at every frame.
            if rest.iter().zip(HEADER).all(|(a, b)| *a == b) {
                break;
            }
            start += 1;
        }
        if start > 0 {
            self.drop_front(start);
        }
    }
}

/// Removes stuffing in place (after every `FF FF FD` of the stream, a following `FD` is dropped);
/// returns the unstuffed length. A sender that did not stuff (the Python SDK's transmit path) is
/// accepted: `FF FF FD` followed by anything else is kept as is.
///
/// Nothing moves before the first `FF FF FD FD`, so that is looked for first (most packets
/// have none: then the region is left as it is); from there on each byte is copied down.
pub fn unstuff(region: &mut [u8]) -> usize {
    let n = region.len();
    let mut k = 2;
    let first = loop {
        if k + 1 >= n {
            return n;
        }
        if region[k] == 0xFD
            && region[k + 1] == 0xFD
            && region[k - 1] == 0xFF
            && region[k - 2] == 0xFF
        {
            break k;
        }
        k += 1;
    };
    // At the first stuffed FD the two bytes before are FF FF, and nothing was dropped yet.
    let (mut i, mut j) = (first, first);
    let (mut p0, mut p1) = (0xFFu8, 0xFFu8);
    while i < region.len() {
        let b = region[i];
        region[j] = b;
        j += 1;
        if b == 0xFD && p0 == 0xFF && p1 == 0xFF && region.get(i + 1) == Some(&0xFD) {
            i += 2;
            p0 = 0xFD;
            p1 = 0xFD;
            continue;
        }
        p0 = p1;
        p1 = b;
        i += 1;
    }
    j
}

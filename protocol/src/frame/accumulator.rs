//! [`FrameAccumulator`]: reassembles frames from a byte stream in any chunking, decoding COBS as
//! bytes arrive so that it holds at most one decoded frame.

use core::fmt;

use serde::de::DeserializeOwned;

use super::{FrameError, decode_message};
use crate::{FRAME_CRC_LEN, MAX_MESSAGE_LEN};

/// Size of the accumulator's buffer: the longest decoded frame (message + CRC).
const DECODED_CAPACITY: usize = MAX_MESSAGE_LEN + FRAME_CRC_LEN;

/// Reassembles frames from a byte stream delivered in any chunking.
///
/// COBS is decoded as bytes arrive, so the buffer holds at most one decoded frame
/// (`MAX_MESSAGE_LEN + FRAME_CRC_LEN` bytes). Garbage and oversized frames end in an error at the
/// next delimiter and the accumulator is ready for the following frame.
#[derive(Clone)]
pub struct FrameAccumulator {
    buf: [u8; DECODED_CAPACITY],
    len: usize,
    /// Bytes left in the current COBS block; 0 means the next byte is a code byte.
    block_left: u8,
    /// Whether the current block ends in an implied zero (its code was not 0xFF).
    zero_pending: bool,
    /// Whether any byte of the current frame has arrived.
    started: bool,
    error: Option<FrameError>,
}

impl fmt::Debug for FrameAccumulator {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("FrameAccumulator")
            .field("len", &self.len)
            .field("error", &self.error)
            .finish_non_exhaustive()
    }
}

impl Default for FrameAccumulator {
    fn default() -> Self {
        Self::new()
    }
}

impl FrameAccumulator {
    /// An empty accumulator (const, so it can live in a `static`).
    pub const fn new() -> Self {
        Self {
            buf: [0; DECODED_CAPACITY],
            len: 0,
            block_left: 0,
            zero_pending: false,
            started: false,
            error: None,
        }
    }

    /// Forgets any partial frame (e.g. after the link dropped).
    pub fn reset(&mut self) {
        self.len = 0;
        self.block_left = 0;
        self.zero_pending = false;
        self.started = false;
        self.error = None;
    }

    fn store(&mut self, byte: u8) {
        match self.buf.get_mut(self.len) {
            Some(slot) => {
                *slot = byte;
                self.len += 1;
            }
            None => self.error = Some(FrameError::TooLong),
        }
    }

    /// Takes one byte. At a delimiter that ends a non-empty frame returns the decoded frame (message
    /// followed by its CRC, see [`decode_message`]) or the reason it is malformed.
    pub fn push(&mut self, byte: u8) -> Option<Result<&[u8], FrameError>> {
        if byte == 0 {
            if !self.started {
                return None;
            }
            let result = match self.error {
                Some(e) => Err(e),
                None if self.block_left != 0 => Err(FrameError::Cobs),
                None => Ok(self.len),
            };
            self.reset();
            return Some(result.map(|len| &self.buf[..len]));
        }
        self.started = true;
        if self.error.is_some() {
            return None;
        }
        if self.block_left == 0 {
            if self.zero_pending {
                self.store(0);
            }
            self.zero_pending = byte != 0xFF;
            self.block_left = byte - 1;
        } else {
            self.store(byte);
            self.block_left -= 1;
        }
        None
    }

    /// Takes one byte and, at the end of a frame, decodes the message.
    pub fn push_message<T: DeserializeOwned>(&mut self, byte: u8) -> Option<Result<T, FrameError>> {
        self.push(byte).map(|frame| frame.and_then(decode_message))
    }

    /// Iterates over the messages (or errors) completed by `input`; a frame that is still incomplete at
    /// the end of `input` stays in the accumulator for the next call.
    pub fn messages<'s, 'i, T: DeserializeOwned>(
        &'s mut self,
        input: &'i [u8],
    ) -> Messages<'s, 'i, T> {
        Messages {
            acc: self,
            input,
            _t: core::marker::PhantomData,
        }
    }
}

/// Iterator returned by [`FrameAccumulator::messages`].
pub struct Messages<'s, 'i, T> {
    acc: &'s mut FrameAccumulator,
    input: &'i [u8],
    _t: core::marker::PhantomData<fn() -> T>,
}

impl<T> fmt::Debug for Messages<'_, '_, T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Messages")
            .field("remaining", &self.input.len())
            .finish()
    }
}

impl<T: DeserializeOwned> Iterator for Messages<'_, '_, T> {
    type Item = Result<T, FrameError>;

    fn next(&mut self) -> Option<Self::Item> {
        while let Some((&byte, rest)) = self.input.split_first() {
            self.input = rest;
            if let Some(item) = self.acc.push_message(byte) {
                return Some(item);
            }
        }
        None
    }
}

//! [`FrameAccumulator`]: reassembles frames from a byte stream in any chunking, decoding COBS as
//! bytes arrive so that it holds at most one decoded frame. Bytes go in one at a time
//! ([`FrameAccumulator::push`]) or a received chunk at a time ([`FrameAccumulator::push_slice`],
//! which copies a block's data in one piece); both decode the same frames and errors.

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

    /// Takes bytes from the front of `input` until one completes a frame, and returns that frame as
    /// [`Self::push`] would have at its delimiter (`input` then starts after the delimiter); `None`
    /// once `input` is used up (it is then empty) with no frame completed.
    ///
    /// The same frames and errors as pushing the bytes one by one, but a block's data is copied in
    /// one piece and the rest of a frame already known to be bad is skipped to the next delimiter
    /// in one search: the per-byte loop was a hot spot of the host's link, which receives chunks.
    pub fn push_slice(&mut self, input: &mut &[u8]) -> Option<Result<&[u8], FrameError>> {
        loop {
            let (&byte, rest) = input.split_first()?;
            if byte == 0 {
                *input = rest;
                if self.started {
                    return self.push(0);
                }
                continue;
            }
            if self.error.is_some() {
                // Bytes up to the next delimiter are dropped.
                let skip = input.iter().position(|&b| b == 0).unwrap_or(input.len());
                *input = &input[skip..];
                continue;
            }
            if self.block_left == 0 {
                // A code byte, as `push` takes it.
                *input = rest;
                self.started = true;
                if self.zero_pending {
                    self.store(0);
                }
                self.zero_pending = byte != 0xFF;
                self.block_left = byte - 1;
                continue;
            }
            // The block's data up to the first zero (which ends the frame, too early).
            let run = usize::from(self.block_left).min(input.len());
            let data_len = input[..run].iter().position(|&b| b == 0).unwrap_or(run);
            let (data, rest) = input.split_at(data_len);
            *input = rest;
            self.started = true;
            let room = DECODED_CAPACITY - self.len;
            if data.len() > room {
                self.buf[self.len..].copy_from_slice(&data[..room]);
                self.len = DECODED_CAPACITY;
                self.error = Some(FrameError::TooLong);
                continue;
            }
            let to = &mut self.buf[self.len..self.len + data.len()];
            if data.len() <= 16 {
                // Most blocks of a message are this short; a loop beats a `memcpy` call.
                for (t, &d) in to.iter_mut().zip(data) {
                    *t = d;
                }
            } else {
                to.copy_from_slice(data);
            }
            self.len += data.len();
            // `data_len <= block_left <= 0xFE`.
            self.block_left -= data.len() as u8;
        }
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
        self.acc
            .push_slice(&mut self.input)
            .map(|frame| frame.and_then(decode_message))
    }
}

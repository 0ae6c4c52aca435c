//! Frame codec: postcard message + CRC-32, COBS-encoded, ended by a zero byte (layout in the crate
//! docs). [`encode_frame`] writes one frame; [`FrameAccumulator`] reassembles frames from bytes in
//! any chunking and reports every malformed frame as a [`FrameError`].

use core::fmt;

use serde::Serialize;
use serde::de::DeserializeOwned;

use crate::{FRAME_CRC_LEN, MAX_FRAME_LEN, MAX_MESSAGE_LEN, crc32};

mod accumulator;
pub use accumulator::{FrameAccumulator, Messages};

/// Why a frame could not be encoded or decoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum FrameError {
    /// The COBS encoding is broken (a block length points past the frame's end).
    Cobs,
    /// The frame is longer than [`MAX_FRAME_LEN`]; its bytes were dropped up to the next delimiter.
    TooLong,
    /// The decoded frame is shorter than its CRC.
    TooShort { len: u16 },
    /// The frame CRC does not match its contents.
    Crc { stored: u32, computed: u32 },
    /// The bytes are not a valid postcard encoding of the expected message type.
    Decode,
    /// The message decoded but bytes were left over.
    TrailingBytes { extra: u16 },
    /// The output buffer (or [`MAX_MESSAGE_LEN`]) is too small for the message.
    BufferTooSmall,
}

impl fmt::Display for FrameError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Cobs => write!(f, "broken COBS encoding"),
            Self::TooLong => write!(f, "frame longer than {MAX_FRAME_LEN} bytes"),
            Self::TooShort { len } => write!(f, "frame of {len} bytes is shorter than its CRC"),
            Self::Crc { stored, computed } => {
                write!(
                    f,
                    "frame CRC {stored:#010x} does not match contents ({computed:#010x})"
                )
            }
            Self::Decode => write!(f, "frame is not a valid message"),
            Self::TrailingBytes { extra } => write!(f, "{extra} bytes after the message"),
            Self::BufferTooSmall => write!(f, "message does not fit the frame buffer"),
        }
    }
}

impl core::error::Error for FrameError {}

/// A postcard flavor that writes the raw message into a slice. Unlike postcard's `Slice` it copies
/// short slices (the varints that make up most of a message) byte by byte instead of calling
/// `memcpy` for each.
struct RawWriter<'b> {
    out: &'b mut [u8],
    pos: usize,
}

impl postcard::ser_flavors::Flavor for RawWriter<'_> {
    type Output = usize;

    #[inline]
    fn try_push(&mut self, data: u8) -> postcard::Result<()> {
        let slot = self
            .out
            .get_mut(self.pos)
            .ok_or(postcard::Error::SerializeBufferFull)?;
        *slot = data;
        self.pos += 1;
        Ok(())
    }

    #[inline]
    fn try_extend(&mut self, data: &[u8]) -> postcard::Result<()> {
        let to = self
            .out
            .get_mut(self.pos..self.pos + data.len())
            .ok_or(postcard::Error::SerializeBufferFull)?;
        if data.len() <= 8 {
            for (t, &d) in to.iter_mut().zip(data) {
                *t = d;
            }
        } else {
            to.copy_from_slice(data);
        }
        self.pos += data.len();
        Ok(())
    }

    fn finalize(self) -> postcard::Result<usize> {
        Ok(self.pos)
    }
}

/// COBS-encodes in place the message and CRC that `buf[1..end]` holds, leaving the frame
/// (delimiter included) at the start of `buf`; returns its length.
///
/// Data bytes stay where they are: each zero becomes the code byte of the block that follows it,
/// and the code byte of a block is written once its end is known. Only a block that fills up (254
/// non-zero bytes) moves the rest right by one, for the code byte of the next block. The blocks
/// are the ones a byte-at-a-time encoder makes: a full block is closed at once, so a frame that
/// ends with one ends with an empty block (code 1).
fn cobs_in_place(buf: &mut [u8], mut end: usize) -> Result<usize, FrameError> {
    let mut code_at = 0;
    let mut from = 1;
    loop {
        // The next zero, within what is left of the current block.
        let block_end = code_at + 0xFF;
        let limit = block_end.min(end);
        match buf[from..limit].iter().position(|&b| b == 0) {
            Some(i) => {
                let zero = from + i;
                buf[code_at] = (zero - code_at) as u8;
                code_at = zero;
                from = zero + 1;
            }
            None if block_end <= end => {
                // The block is full: its code is 0xFF and the next block's code byte goes in at
                // `block_end`, so the bytes after it move right by one.
                if end >= buf.len() {
                    return Err(FrameError::BufferTooSmall);
                }
                buf.copy_within(block_end..end, block_end + 1);
                buf[code_at] = 0xFF;
                code_at = block_end;
                from = block_end + 1;
                end += 1;
            }
            None => break,
        }
    }
    buf[code_at] = (end - code_at) as u8;
    *buf.get_mut(end).ok_or(FrameError::BufferTooSmall)? = 0;
    Ok(end + 1)
}

/// Encodes `message` as one frame (delimiter included) into `buf`; returns the frame's bytes.
///
/// A buffer of [`MAX_FRAME_LEN`] bytes always suffices for the messages of this crate.
pub fn encode_frame<'b, T: Serialize + ?Sized>(
    message: &T,
    buf: &'b mut [u8],
) -> Result<&'b [u8], FrameError> {
    // The message goes to `buf[1..]`, where its bytes stay in the frame (one code byte before
    // them); the CRC is taken over them in one piece and follows them; then COBS is done in
    // place. No scratch buffer, and on the host the sliced CRC runs over the whole message (a
    // byte-at-a-time encoder that kept a running CRC was a hot spot of the link). Whatever does
    // not fit (a message past MAX_MESSAGE_LEN, a frame past `buf`) is BufferTooSmall.
    let body = buf.len().min(1 + MAX_MESSAGE_LEN);
    let raw = buf.get_mut(1..body).ok_or(FrameError::BufferTooSmall)?;
    let len = postcard::serialize_with_flavor(message, RawWriter { out: raw, pos: 0 })
        .map_err(|_| FrameError::BufferTooSmall)?;
    let crc = crc32::checksum(&buf[1..1 + len]);
    let end = 1 + len + FRAME_CRC_LEN;
    buf.get_mut(1 + len..end)
        .ok_or(FrameError::BufferTooSmall)?
        .copy_from_slice(&crc.to_le_bytes());
    let frame_len = cobs_in_place(buf, end)?;
    Ok(&buf[..frame_len])
}

/// Encodes `message` as one frame into a new `Vec` (host side).
#[cfg(feature = "std")]
pub fn encode_frame_vec<T: Serialize + ?Sized>(message: &T) -> Result<Vec<u8>, FrameError> {
    let mut buf = vec![0u8; MAX_FRAME_LEN];
    let len = encode_frame(message, &mut buf)?.len();
    buf.truncate(len);
    Ok(buf)
}

/// Checks the CRC of a decoded frame (message + CRC) and decodes the message.
pub fn decode_message<T: DeserializeOwned>(decoded: &[u8]) -> Result<T, FrameError> {
    let Some(body_len) = decoded.len().checked_sub(FRAME_CRC_LEN) else {
        return Err(FrameError::TooShort {
            len: decoded.len() as u16,
        });
    };
    let (body, crc) = decoded.split_at(body_len);
    let stored = u32::from_le_bytes([crc[0], crc[1], crc[2], crc[3]]);
    let computed = crc32::checksum(body);
    if stored != computed {
        return Err(FrameError::Crc { stored, computed });
    }
    let (value, rest) = postcard::take_from_bytes::<T>(body).map_err(|_| FrameError::Decode)?;
    if !rest.is_empty() {
        return Err(FrameError::TrailingBytes {
            extra: rest.len() as u16,
        });
    }
    Ok(value)
}

#[cfg(test)]
mod tests;

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

/// A postcard flavor that COBS-encodes on the fly into a slice and keeps a CRC of the raw bytes,
/// so encoding needs no scratch buffer.
struct CobsCrcWriter<'b> {
    out: &'b mut [u8],
    /// Index of the code byte of the block being written.
    code_at: usize,
    /// Next free index.
    pos: usize,
    raw_len: usize,
    crc: crc::Digest<'static, u32>,
}

impl<'b> CobsCrcWriter<'b> {
    fn new(out: &'b mut [u8]) -> Result<Self, FrameError> {
        if out.is_empty() {
            return Err(FrameError::BufferTooSmall);
        }
        Ok(Self {
            out,
            code_at: 0,
            pos: 1,
            raw_len: 0,
            crc: crc32::digest(),
        })
    }

    fn close_block(&mut self) -> Result<(), FrameError> {
        let code = self.pos - self.code_at;
        self.out[self.code_at] = code as u8;
        self.code_at = self.pos;
        *self
            .out
            .get_mut(self.pos)
            .ok_or(FrameError::BufferTooSmall)? = 0;
        self.pos += 1;
        Ok(())
    }

    fn push_cobs(&mut self, byte: u8) -> Result<(), FrameError> {
        if byte == 0 {
            return self.close_block();
        }
        *self
            .out
            .get_mut(self.pos)
            .ok_or(FrameError::BufferTooSmall)? = byte;
        self.pos += 1;
        if self.pos - self.code_at == 0xFF {
            self.close_block()?;
        }
        Ok(())
    }

    /// Appends the CRC, closes the last block and the frame; returns the frame length.
    fn finish(mut self) -> Result<usize, FrameError> {
        let crc = self.crc.clone().finalize();
        for b in crc.to_le_bytes() {
            self.push_cobs(b)?;
        }
        let code = self.pos - self.code_at;
        self.out[self.code_at] = code as u8;
        *self
            .out
            .get_mut(self.pos)
            .ok_or(FrameError::BufferTooSmall)? = 0;
        Ok(self.pos + 1)
    }
}

impl postcard::ser_flavors::Flavor for CobsCrcWriter<'_> {
    type Output = usize;

    fn try_push(&mut self, data: u8) -> postcard::Result<()> {
        self.raw_len += 1;
        if self.raw_len > MAX_MESSAGE_LEN {
            return Err(postcard::Error::SerializeBufferFull);
        }
        self.crc.update(&[data]);
        self.push_cobs(data)
            .map_err(|_| postcard::Error::SerializeBufferFull)
    }

    fn finalize(self) -> postcard::Result<usize> {
        self.finish()
            .map_err(|_| postcard::Error::SerializeBufferFull)
    }
}

/// Encodes `message` as one frame (delimiter included) into `buf`; returns the frame's bytes.
///
/// A buffer of [`MAX_FRAME_LEN`] bytes always suffices for the messages of this crate.
pub fn encode_frame<'b, T: Serialize + ?Sized>(
    message: &T,
    buf: &'b mut [u8],
) -> Result<&'b [u8], FrameError> {
    let writer = CobsCrcWriter::new(&mut *buf)?;
    let len =
        postcard::serialize_with_flavor(message, writer).map_err(|_| FrameError::BufferTooSmall)?;
    Ok(&buf[..len])
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

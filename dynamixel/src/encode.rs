//! Instruction (and status) packet encoder: header, byte stuffing from INST to the last
//! parameter, LEN over the stuffed bytes, CRC over the stuffed packet. Writes into a caller's
//! buffer, no alloc.

use crate::crc;
use crate::instruction::{BROADCAST_ID, Instruction, STATUS};

/// The four header bytes of every packet.
pub const HEADER: [u8; 4] = [0xFF, 0xFF, 0xFD, 0x00];
/// Bytes before INST: header, ID, LEN_L, LEN_H.
pub const PRE_INST: usize = 7;

/// Why a packet could not be encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum EncodeError {
    /// The packet needs more than `capacity` bytes.
    BufferTooSmall { capacity: usize },
    /// A Sync/Bulk entry's data length differs from the declared length.
    DataLength { id: u8, expected: usize, got: usize },
    /// An ID above 252 where a servo ID is needed (or the broadcast ID where it is not allowed).
    BadId { id: u8 },
}

/// Builds one packet in place: push parameters (stuffed on the fly), then `finish`.
#[derive(Debug)]
pub struct PacketWriter<'a> {
    buf: &'a mut [u8],
    len: usize,
    // The last two unstuffed bytes, to spot FF FF FD.
    prev: [u8; 2],
    overflow: bool,
}

impl<'a> PacketWriter<'a> {
    /// Starts a packet to `id` with instruction byte `inst`.
    pub fn new(buf: &'a mut [u8], id: u8, inst: u8) -> Result<Self, EncodeError> {
        if buf.len() < PRE_INST + 3 {
            return Err(EncodeError::BufferTooSmall {
                capacity: buf.len(),
            });
        }
        buf[..4].copy_from_slice(&HEADER);
        buf[4] = id;
        let mut w = Self {
            buf,
            len: PRE_INST,
            prev: [0, 0],
            overflow: false,
        };
        w.push(inst);
        Ok(w)
    }

    /// Appends one unstuffed byte.
    #[inline]
    pub fn push(&mut self, b: u8) {
        self.put(b);
        if b == 0xFD && self.prev == [0xFF, 0xFF] {
            self.put(0xFD);
        }
        self.prev = [self.prev[1], b];
    }

    /// Appends unstuffed bytes: copied at once when they fit and hold no `FD` (so nothing
    /// needs stuffing), byte by byte through [`Self::push`] otherwise.
    pub fn extend(&mut self, bytes: &[u8]) {
        let n = bytes.len();
        // `put`'s room rule for each byte: two bytes left free for the CRC.
        if n > 0 && self.len + n + 2 <= self.buf.len() && !bytes.contains(&0xFD) {
            self.buf[self.len..self.len + n].copy_from_slice(bytes);
            self.len += n;
            self.prev = if n >= 2 {
                [bytes[n - 2], bytes[n - 1]]
            } else {
                [self.prev[1], bytes[0]]
            };
            return;
        }
        for &b in bytes {
            self.push(b);
        }
    }

    #[inline]
    fn put(&mut self, b: u8) {
        // Keep two bytes free for the CRC.
        if self.len + 2 < self.buf.len() {
            self.buf[self.len] = b;
            self.len += 1;
        } else {
            self.overflow = true;
        }
    }

    /// Writes LEN and CRC; returns the packet length in bytes.
    pub fn finish(self) -> Result<usize, EncodeError> {
        if self.overflow || self.len + 2 > self.buf.len() {
            return Err(EncodeError::BufferTooSmall {
                capacity: self.buf.len(),
            });
        }
        let field = (self.len - PRE_INST + 2) as u16;
        self.buf[5..7].copy_from_slice(&field.to_le_bytes());
        let c = crc::crc16(&self.buf[..self.len]);
        self.buf[self.len..self.len + 2].copy_from_slice(&c.to_le_bytes());
        Ok(self.len + 2)
    }
}

fn check_id(id: u8) -> Result<(), EncodeError> {
    if id > crate::instruction::MAX_ID && id != BROADCAST_ID {
        return Err(EncodeError::BadId { id });
    }
    Ok(())
}

fn simple(buf: &mut [u8], id: u8, inst: Instruction, params: &[u8]) -> Result<usize, EncodeError> {
    check_id(id)?;
    let mut w = PacketWriter::new(buf, id, inst as u8)?;
    w.extend(params);
    w.finish()
}

/// Ping `id` (or broadcast).
pub fn ping(buf: &mut [u8], id: u8) -> Result<usize, EncodeError> {
    simple(buf, id, Instruction::Ping, &[])
}

/// Read `len` bytes at `addr` of servo `id`.
pub fn read(buf: &mut [u8], id: u8, addr: u16, len: u16) -> Result<usize, EncodeError> {
    let a = addr.to_le_bytes();
    let l = len.to_le_bytes();
    simple(buf, id, Instruction::Read, &[a[0], a[1], l[0], l[1]])
}

/// Write `data` at `addr` of servo `id`.
pub fn write(buf: &mut [u8], id: u8, addr: u16, data: &[u8]) -> Result<usize, EncodeError> {
    check_id(id)?;
    let mut w = PacketWriter::new(buf, id, Instruction::Write as u8)?;
    w.extend(&addr.to_le_bytes());
    w.extend(data);
    w.finish()
}

/// Reboot servo `id`: clears a hardware error and Torque Enable.
pub fn reboot(buf: &mut [u8], id: u8) -> Result<usize, EncodeError> {
    simple(buf, id, Instruction::Reboot, &[])
}

/// Sync Read `len` bytes at `addr` from each of `ids`; they reply in list order.
pub fn sync_read(buf: &mut [u8], addr: u16, len: u16, ids: &[u8]) -> Result<usize, EncodeError> {
    let mut w = PacketWriter::new(buf, BROADCAST_ID, Instruction::SyncRead as u8)?;
    w.extend(&addr.to_le_bytes());
    w.extend(&len.to_le_bytes());
    for &id in ids {
        servo_id(id)?;
        w.push(id);
    }
    w.finish()
}

/// Sync Write `len` bytes at `addr` to each `(id, data)`.
pub fn sync_write<'d>(
    buf: &mut [u8],
    addr: u16,
    len: u16,
    entries: impl IntoIterator<Item = (u8, &'d [u8])>,
) -> Result<usize, EncodeError> {
    let mut w = PacketWriter::new(buf, BROADCAST_ID, Instruction::SyncWrite as u8)?;
    w.extend(&addr.to_le_bytes());
    w.extend(&len.to_le_bytes());
    for (id, data) in entries {
        servo_id(id)?;
        if data.len() != len as usize {
            return Err(EncodeError::DataLength {
                id,
                expected: len as usize,
                got: data.len(),
            });
        }
        w.push(id);
        w.extend(data);
    }
    w.finish()
}

/// Sync Write of one 4-byte value per servo (goal positions): the bus cycle's hot path.
pub fn sync_write_u32(
    buf: &mut [u8],
    addr: u16,
    entries: impl IntoIterator<Item = (u8, u32)>,
) -> Result<usize, EncodeError> {
    let mut w = PacketWriter::new(buf, BROADCAST_ID, Instruction::SyncWrite as u8)?;
    w.extend(&addr.to_le_bytes());
    w.extend(&4u16.to_le_bytes());
    for (id, value) in entries {
        servo_id(id)?;
        w.push(id);
        w.extend(&value.to_le_bytes());
    }
    w.finish()
}

/// Bulk Read: `(id, addr, len)` per servo; they reply in list order.
pub fn bulk_read(buf: &mut [u8], entries: &[(u8, u16, u16)]) -> Result<usize, EncodeError> {
    let mut w = PacketWriter::new(buf, BROADCAST_ID, Instruction::BulkRead as u8)?;
    for &(id, addr, len) in entries {
        servo_id(id)?;
        w.push(id);
        w.extend(&addr.to_le_bytes());
        w.extend(&len.to_le_bytes());
    }
    w.finish()
}

/// Bulk Write: `(id, addr, data)` per servo.
pub fn bulk_write<'d>(
    buf: &mut [u8],
    entries: impl IntoIterator<Item = (u8, u16, &'d [u8])>,
) -> Result<usize, EncodeError> {
    let mut w = PacketWriter::new(buf, BROADCAST_ID, Instruction::BulkWrite as u8)?;
    for (id, addr, data) in entries {
        servo_id(id)?;
        w.push(id);
        w.extend(&addr.to_le_bytes());
        w.extend(&(data.len() as u16).to_le_bytes());
        w.extend(data);
    }
    w.finish()
}

/// A status packet (what a servo sends): used by the virtual chain.
pub fn status(buf: &mut [u8], id: u8, error: u8, params: &[u8]) -> Result<usize, EncodeError> {
    let mut w = PacketWriter::new(buf, id, STATUS)?;
    w.push(error);
    w.extend(params);
    w.finish()
}

fn servo_id(id: u8) -> Result<(), EncodeError> {
    if id > crate::instruction::MAX_ID {
        return Err(EncodeError::BadId { id });
    }
    Ok(())
}

impl core::fmt::Display for EncodeError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            EncodeError::BufferTooSmall { capacity } => {
                write!(f, "packet does not fit in {capacity} bytes")
            }
            EncodeError::DataLength { id, expected, got } => {
                write!(
                    f,
                    "entry for ID {id} has {got} data bytes, the packet declares {expected}"
                )
            }
            EncodeError::BadId { id } => write!(f, "ID {id} is not a servo ID (0..=252)"),
        }
    }
}

impl core::error::Error for EncodeError {}

//! The commit record at the start of every bank: written last, after the table's CRC has been checked
//! on what actually sits in flash, so a bank without a valid record is never read as a gait.

/// CRC-32 (ISO-HDLC, the zlib / PNG one) over table bytes and records.
pub const CRC32: crc::Crc<u32> = crc::Crc::<u32>::new(&crc::CRC_32_ISO_HDLC);

/// Bytes reserved at the start of a bank before the table; keeps the table 256-byte (page) aligned.
pub const HEADER: usize = 256;
/// Bytes of an encoded record.
pub const RECORD_LEN: usize = 24;
/// "DGTS" little-endian: marks a committed bank.
const MAGIC: u32 = u32::from_le_bytes(*b"DGTS");

/// What a committed bank holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Record {
    /// Slot the bank belongs to (guards against a record read from the wrong place).
    pub slot: u16,
    /// Bank within the slot, 0 (A) or 1 (B).
    pub bank: u16,
    /// Increases with every commit to the slot; the valid bank with the larger one is current.
    pub seq: u32,
    /// Length of the table in bytes.
    pub len: u32,
    /// CRC-32 of the table bytes.
    pub crc: u32,
}

impl Record {
    /// Little-endian bytes: magic, slot, bank, seq, len, crc, then the CRC-32 of those 20 bytes.
    pub fn encode(&self) -> [u8; RECORD_LEN] {
        let mut b = [0u8; RECORD_LEN];
        b[0..4].copy_from_slice(&MAGIC.to_le_bytes());
        b[4..6].copy_from_slice(&self.slot.to_le_bytes());
        b[6..8].copy_from_slice(&self.bank.to_le_bytes());
        b[8..12].copy_from_slice(&self.seq.to_le_bytes());
        b[12..16].copy_from_slice(&self.len.to_le_bytes());
        b[16..20].copy_from_slice(&self.crc.to_le_bytes());
        let crc = CRC32.checksum(&b[0..20]);
        b[20..24].copy_from_slice(&crc.to_le_bytes());
        b
    }

    /// The record in `b`, if its magic and its own CRC hold (a torn or erased record gives `None`).
    pub fn decode(b: &[u8]) -> Option<Self> {
        let b = b.get(..RECORD_LEN)?;
        let word = |i: usize| u32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
        let half = |i: usize| u16::from_le_bytes([b[i], b[i + 1]]);
        if word(0) != MAGIC || word(20) != CRC32.checksum(&b[0..20]) {
            return None;
        }
        Some(Self {
            slot: half(4),
            bank: half(6),
            seq: word(8),
            len: word(12),
            crc: word(16),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc32_matches_the_published_check_value() {
        // Check value of CRC-32/ISO-HDLC from the CRC catalogue (reveng): "123456789" -> 0xCBF43926.
        assert_eq!(CRC32.checksum(b"123456789"), 0xCBF4_3926);
    }

    #[test]
    fn record_layout_is_little_endian_with_a_trailing_crc() {
        let r = Record {
            slot: 2,
            bank: 1,
            seq: 0x0102_0304,
            len: 100,
            crc: 0xAABB_CCDD,
        };
        let b = r.encode();
        assert_eq!(&b[0..4], b"DGTS");
        assert_eq!(&b[4..8], &[2, 0, 1, 0]);
        assert_eq!(&b[8..12], &[4, 3, 2, 1]);
        assert_eq!(&b[12..16], &[100, 0, 0, 0]);
        assert_eq!(&b[16..20], &[0xDD, 0xCC, 0xBB, 0xAA]);
        assert_eq!(Record::decode(&b), Some(r));
    }

    #[test]
    fn any_flipped_bit_or_erased_record_is_rejected() {
        let b = Record {
            slot: 0,
            bank: 0,
            seq: 7,
            len: 5,
            crc: 9,
        }
        .encode();
        for i in 0..RECORD_LEN * 8 {
            let mut c = b;
            c[i / 8] ^= 1 << (i % 8);
            assert_eq!(Record::decode(&c), None, "bit {i}");
        }
        assert_eq!(Record::decode(&[0xFF; RECORD_LEN]), None);
        assert_eq!(Record::decode(&b[..RECORD_LEN - 1]), None);
    }
}

//! CRC-16 of Protocol 2.0: polynomial 0x8005, init 0, no reflection, no final xor
//! (CRC-16/UMTS, also called BUYPASS). Table-driven, the table built at compile time.
//!
//! With `std` (the host: the simulated wire, where every packet is checked on both ends) eight
//! bytes are taken at a time through eight tables (4 KB, "slicing-by-8"): the byte-wise loop's
//! one table lookup per byte waits on the previous one, the eight of a block do not. The
//! firmware keeps the one 512-byte table. Both give the same CRC (a test checks them against
//! each other and the catalogue).

const POLY: u16 = 0x8005;

const TABLE: [u16; 256] = build_table();

const fn build_table() -> [u16; 256] {
    let mut table = [0u16; 256];
    let mut i = 0;
    while i < 256 {
        let mut crc = (i as u16) << 8;
        let mut bit = 0;
        while bit < 8 {
            crc = if crc & 0x8000 != 0 {
                (crc << 1) ^ POLY
            } else {
                crc << 1
            };
            bit += 1;
        }
        table[i] = crc;
        i += 1;
    }
    table
}

/// `SLICES[k][b]`: the CRC of byte `b` followed by `k` zero bytes (`SLICES[0]` is [`TABLE`]).
#[cfg(feature = "std")]
static SLICES: [[u16; 256]; 8] = build_slices();

#[cfg(feature = "std")]
const fn build_slices() -> [[u16; 256]; 8] {
    let mut t = [[0u16; 256]; 8];
    t[0] = TABLE;
    let mut k = 1;
    while k < 8 {
        let mut i = 0;
        while i < 256 {
            let prev = t[k - 1][i];
            t[k][i] = (prev << 8) ^ TABLE[(prev >> 8) as usize];
            i += 1;
        }
        k += 1;
    }
    t
}

/// Continues a CRC over `bytes` one byte at a time (start with 0).
#[inline]
fn update_bytewise(mut crc: u16, bytes: &[u8]) -> u16 {
    for &b in bytes {
        let idx = ((crc >> 8) as u8 ^ b) as usize;
        crc = (crc << 8) ^ TABLE[idx];
    }
    crc
}

/// Continues a CRC over `bytes` (start with 0).
#[cfg(not(feature = "std"))]
#[inline]
pub fn update(crc: u16, bytes: &[u8]) -> u16 {
    update_bytewise(crc, bytes)
}

/// Continues a CRC over `bytes` (start with 0), eight bytes at a time.
#[cfg(feature = "std")]
pub fn update(mut crc: u16, bytes: &[u8]) -> u16 {
    let t = &SLICES;
    let mut blocks = bytes.chunks_exact(8);
    for b in &mut blocks {
        crc = t[7][((crc >> 8) as u8 ^ b[0]) as usize]
            ^ t[6][(crc as u8 ^ b[1]) as usize]
            ^ t[5][b[2] as usize]
            ^ t[4][b[3] as usize]
            ^ t[3][b[4] as usize]
            ^ t[2][b[5] as usize]
            ^ t[1][b[6] as usize]
            ^ t[0][b[7] as usize];
    }
    update_bytewise(crc, blocks.remainder())
}

/// CRC of a whole byte string.
#[inline]
pub fn crc16(bytes: &[u8]) -> u16 {
    update(0, bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn catalogue_check_value() {
        // The check value of the CRC catalogue for CRC-16/UMTS.
        assert_eq!(crc16(b"123456789"), 0xFEE8);
    }

    #[test]
    fn the_tables_agree_with_the_byte_wise_loop() {
        // Every length across block boundaries, from every starting CRC a packet can leave.
        let bytes: Vec<u8> = (0u32..300).map(|i| (i * 151 + 7) as u8).collect();
        for len in 0..bytes.len() {
            for start in [0u16, 0x4E19, 0xFFFF, 0x8005] {
                assert_eq!(
                    update(start, &bytes[..len]),
                    update_bytewise(start, &bytes[..len]),
                    "length {len}, start {start:#06x}"
                );
            }
        }
    }

    #[test]
    fn ping_vector_crc() {
        // e-manual: Ping ID 1 ends in CRC bytes 19 4E (little endian 0x4E19).
        assert_eq!(
            crc16(&[0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x03, 0x00, 0x01]),
            0x4E19
        );
    }
}

//! CRC-16 of Protocol 2.0: polynomial 0x8005, init 0, no reflection, no final xor
//! (CRC-16/UMTS, also called BUYPASS). Table-driven, the table built at compile time.

const POLY: u16 = 0x8005;

const TABLE: [u16; 256] = build_table();

const fn build_table() -> [u16; 256] {
    let mut table = [0u16; 256];
    let mut i = 0;
    while i < 256 {
        let mut crc = (i as u16) << 8;
        let mut bit = 0;
        while bit < 8 {
            crc = if crc & 0x8000 != 0 { (crc << 1) ^ POLY } else { crc << 1 };
            bit += 1;
        }
        table[i] = crc;
        i += 1;
    }
    table
}

/// Continues a CRC over `bytes` (start with 0).
#[inline]
pub fn update(mut crc: u16, bytes: &[u8]) -> u16 {
    for &b in bytes {
        let idx = ((crc >> 8) as u8 ^ b) as usize;
        crc = (crc << 8) ^ TABLE[idx];
    }
    crc
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
    fn ping_vector_crc() {
        // e-manual: Ping ID 1 ends in CRC bytes 19 4E (little endian 0x4E19).
        assert_eq!(crc16(&[0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x03, 0x00, 0x01]), 0x4E19);
    }
}

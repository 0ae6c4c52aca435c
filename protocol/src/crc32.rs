//! The CRC-32 used by frames, gait tables and uploads: CRC-32/ISO-HDLC (zlib, Ethernet).

use crc::{CRC_32_ISO_HDLC, Crc, Digest};

/// The algorithm instance (a 1 KB table in flash).
pub static CRC32: Crc<u32> = Crc::<u32>::new(&CRC_32_ISO_HDLC);

/// CRC-32/ISO-HDLC of `bytes`.
pub fn checksum(bytes: &[u8]) -> u32 {
    CRC32.checksum(bytes)
}

/// A running CRC-32/ISO-HDLC over bytes that arrive in pieces.
pub fn digest() -> Digest<'static, u32> {
    CRC32.digest()
}

#[cfg(test)]
mod tests {
    #[test]
    fn check_value_of_the_catalogue() {
        // The CRC catalogue's check value for "123456789" (reveng.sourceforge.io, CRC-32/ISO-HDLC).
        assert_eq!(super::checksum(b"123456789"), 0xCBF4_3926);
    }
}

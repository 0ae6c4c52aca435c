//! The CRC-32 used by frames, gait tables and uploads: CRC-32/ISO-HDLC (zlib, Ethernet).
//!
//! The firmware (no `std`) computes it bytewise from a 1 KB table in flash. The host (`std`)
//! computes the same values from a 16 KB slice-by-16 table, which takes 16 bytes per step: the
//! host checks every frame of the link (and of the simulated board's side), where the bytewise
//! loop was a hot spot.

use crc::{CRC_32_ISO_HDLC, Crc};

/// The table layout: slice-by-16 (16 KB) on the host, bytewise (1 KB) on the firmware.
#[cfg(feature = "std")]
pub type Table = crc::Table<16>;
/// The table layout: slice-by-16 (16 KB) on the host, bytewise (1 KB) on the firmware.
#[cfg(not(feature = "std"))]
pub type Table = crc::Table<1>;

/// A running CRC-32 ([`digest`]); the table type is [`Table`].
pub type Digest = crc::Digest<'static, u32, Table>;

/// The algorithm instance (a 1 KB table in flash on the firmware, 16 KB on the host).
pub static CRC32: Crc<u32, Table> = Crc::<u32, Table>::new(&CRC_32_ISO_HDLC);

/// CRC-32/ISO-HDLC of `bytes`.
pub fn checksum(bytes: &[u8]) -> u32 {
    CRC32.checksum(bytes)
}

/// A running CRC-32/ISO-HDLC over bytes that arrive in pieces.
pub fn digest() -> Digest {
    CRC32.digest()
}

#[cfg(test)]
mod tests {
    use crc::{CRC_32_ISO_HDLC, Crc};

    /// The bytewise reference (the crate's default 1-table implementation), independent of
    /// [`super::Table`].
    const BYTEWISE: Crc<u32> = Crc::<u32>::new(&CRC_32_ISO_HDLC);

    #[test]
    fn check_value_of_the_catalogue() {
        // The CRC catalogue's check value for "123456789" (reveng.sourceforge.io, CRC-32/ISO-HDLC).
        assert_eq!(super::checksum(b"123456789"), 0xCBF4_3926);
        assert_eq!(BYTEWISE.checksum(b"123456789"), 0xCBF4_3926);
        let mut d = super::digest();
        d.update(b"1234");
        d.update(b"56789");
        assert_eq!(d.finalize(), 0xCBF4_3926);
    }

    /// Bytes that are neither all zero nor periodic within a slice-by-16 step.
    fn bytes(len: usize) -> impl Iterator<Item = u8> {
        let mut s: u32 = 0x1234_5678;
        (0..len).map(move |_| {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (s >> 24) as u8
        })
    }

    #[test]
    fn equals_the_bytewise_crc_at_every_length() {
        let data: [u8; 300] = core::array::from_fn({
            let mut it = bytes(300);
            move |_| it.next().unwrap_or(0)
        });
        for len in 0..300 {
            let want = BYTEWISE.checksum(&data[..len]);
            assert_eq!(super::checksum(&data[..len]), want, "length {len}");
            // A running digest split anywhere, including around the 16-byte steps.
            for split in [0, 1, 3, 7, 15, 16, 17, 31, 32, 33, 100, 255] {
                let split = split.min(len);
                let mut d = super::digest();
                d.update(&data[..split]);
                d.update(&data[split..len]);
                assert_eq!(d.finalize(), want, "length {len}, split at {split}");
            }
            // ... and byte by byte.
            let mut d = super::digest();
            for b in &data[..len] {
                d.update(core::slice::from_ref(b));
            }
            assert_eq!(d.finalize(), want, "length {len}, bytewise");
        }
        // All zeros and all ones as well (no accidental dependence on the pattern).
        for fill in [0u8, 0xFF] {
            for len in 0..300 {
                let data = [fill; 300];
                assert_eq!(
                    super::checksum(&data[..len]),
                    BYTEWISE.checksum(&data[..len]),
                    "{len} bytes of {fill:#04x}"
                );
            }
        }
    }
}

//! A gait table laid out by hand, shared by the golden and the validation tests.

/// A 1-joint, 1-slice table laid out by hand from the format table in `gait/mod.rs`.
/// CRC-32 of the first 58 bytes (zlib.crc32) = 0x8567F1A7.
pub const GOLDEN_TABLE: [u8; 62] = [
    b'D', b'B', b'G', b'T', // magic
    0x01, 0x00, // format version 1
    0x01, 0x00, // 1 joint, reserved
    0x01, 0x00, // 1 slice
    0x88, 0x13, // duty 5000 = 0.5
    0x40, 0x42, 0x0F, 0x00, // period 1_000_000 us
    0x3E, 0x00, 0x00, 0x00, // total length 62 = 36 + 16 + (2 + 4) + 4
    b't', b'r', b'i', b'p', b'o', b'd', 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, // name
    0x01, 0x01, 0xFF, 0x00, // servo 1, MX-64, sign -1, reserved
    0x00, 0x08, // zero offset 2048 ticks
    0x68, 0xC5, // min -1.5 rad = -15000 = 0xC568
    0x98, 0x3A, // max 1.5 rad = 15000
    0x00, 0x00, // reserved
    0xD0, 0x20, 0x00, 0x00, // stiffness 8.4 N m/rad = 8400 mN m/rad
    0x09, 0x00, // stance: LF (bit 0) and RF (bit 3), reserved
    0xC4, 0x09, // angle 0.25 rad = 2500
    0x50, 0xFB, // torque -1.2 N m = -1200
    0xA7, 0xF1, 0x67, 0x85, // CRC-32
];

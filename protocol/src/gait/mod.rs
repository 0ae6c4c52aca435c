//! The step-table (gait table) format: a header, a per-joint map, then per slice the stance flags and
//! per joint the planned angle and torque, all little-endian, closed by a CRC-32.
//!
//! ```text
//! offset        size  field
//! 0             4     magic "DBGT"
//! 4             2     format version (FORMAT_VERSION)
//! 6             1     joint count J (1 ..= MAX_JOINTS)
//! 7             1     reserved, 0
//! 8             2     slice count S (1 ..= MAX_SLICES)
//! 10            2     duty factor, 1e-4 of the period (1 ..= 9999)
//! 12            4     step period, us (> 0)
//! 16            4     total length of the table in bytes, CRC included
//! 20            16    name, UTF-8, NUL-padded
//! 36            16*J  joint map, one record per joint (JointMap):
//!                       +0 servo ID u8, +1 model u8 (0 MX-28, 1 MX-64), +2 sign i8 (+1/-1),
//!                       +3 leg u8 (0 not given, 1..=6 LF LM LH RF RM RH),
//!                       +4 zero offset u16 ticks (0..=4095), +6 min angle i16,
//!                       +8 max angle i16, +10 reserved u16 0, +12 stiffness u32 mN m/rad (> 0)
//! 36+16J        S*(2+4J) slices: stance u8 (bit i = leg i in LF LM LH RF RM RH), reserved u8 0,
//!                       then per joint angle i16 (1e-4 rad) and torque i16 (mN m)
//! total-4       4     CRC-32/ISO-HDLC of bytes [0, total-4)
//! ```
//!
//! 22 joints x 1000 slices take 36 + 352 + 1000 * 90 + 4 = 90 392 bytes. Nothing needs alignment,
//! so the firmware reads a table in place from XIP flash through [`GaitTable`].

#[cfg(feature = "std")]
mod builder;
mod error;
mod header;
mod joint;
mod view;

#[cfg(feature = "std")]
pub use builder::{BuildError, Field, GaitTableBuilder, JointSpec};
pub use error::{JointField, TableError};
pub use header::{GaitHeader, printable_name};
pub use joint::{JointMap, ServoModel, Sign};
pub use view::{GaitTable, Sample, SliceView};

/// First four bytes of every table.
pub const MAGIC: [u8; 4] = *b"DBGT";
/// Version of the table layout; bumped on every change of it. (The joint record's leg byte was
/// reserved, 0, before it named the leg: a table of before reads as one whose legs are not
/// given, so the layout kept its version.)
pub const FORMAT_VERSION: u16 = 1;
/// Bytes of the header.
pub const HEADER_LEN: usize = 36;
/// Bytes of one joint record.
pub const JOINT_RECORD_LEN: usize = 16;
/// Bytes before the samples of a slice (stance flags, reserved byte).
pub const SLICE_PREFIX_LEN: usize = 2;
/// Bytes of one sample (angle i16, torque i16).
pub const SAMPLE_LEN: usize = 4;
/// Bytes of the trailing CRC.
pub const CRC_LEN: usize = 4;
/// Bytes of a table name.
pub const NAME_LEN: usize = 16;
/// Most slices per step.
pub const MAX_SLICES: u16 = 10_000;
/// Number of legs, and so of stance bits.
pub const LEGS: usize = 6;
/// Stance bits that may be set.
pub const STANCE_MASK: u8 = (1 << LEGS) - 1;

/// Length in bytes of a table of `joints` joints and `slices` slices.
pub const fn table_len(joints: usize, slices: usize) -> usize {
    HEADER_LEN + joints * JOINT_RECORD_LEN + slices * slice_len(joints) + CRC_LEN
}

/// Bytes of one slice of a table with `joints` joints.
pub const fn slice_len(joints: usize) -> usize {
    SLICE_PREFIX_LEN + joints * SAMPLE_LEN
}

pub(crate) fn le_u16(b: &[u8], at: usize) -> u16 {
    u16::from_le_bytes([b[at], b[at + 1]])
}

pub(crate) fn le_i16(b: &[u8], at: usize) -> i16 {
    i16::from_le_bytes([b[at], b[at + 1]])
}

pub(crate) fn le_u32(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

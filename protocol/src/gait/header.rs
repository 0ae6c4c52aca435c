//! The table header: what `UploadBegin` announces and `ListGaits` reports.

use super::{NAME_LEN, table_len};

/// The shape and timing of a gait table (its header without magic, version and length).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GaitHeader {
    /// Joints per slice.
    pub joint_count: u8,
    /// Slices per step.
    pub slice_count: u16,
    /// Planned step period, microseconds.
    pub step_period_us: u32,
    /// Fraction of the step a leg is in stance, 1e-4 (e.g. 5000 = 0.5).
    pub duty: u16,
    /// Name, UTF-8, NUL-padded.
    pub name: [u8; NAME_LEN],
}

impl GaitHeader {
    /// Length in bytes of the table this header describes, CRC included.
    pub fn table_len(&self) -> u32 {
        table_len(usize::from(self.joint_count), usize::from(self.slice_count)) as u32
    }

    /// The header at the start of `bytes` if its magic and format version hold and its counts are
    /// in range, without checking the table's CRC: for naming a table that is known to be damaged.
    pub fn peek(bytes: &[u8]) -> Option<Self> {
        let b = bytes.get(..super::HEADER_LEN)?;
        if b[0..4] != super::MAGIC || u16::from_le_bytes([b[4], b[5]]) != super::FORMAT_VERSION {
            return None;
        }
        let mut name = [0u8; NAME_LEN];
        name.copy_from_slice(&b[20..20 + NAME_LEN]);
        let h = Self {
            joint_count: b[6],
            slice_count: u16::from_le_bytes([b[8], b[9]]),
            duty: u16::from_le_bytes([b[10], b[11]]),
            step_period_us: u32::from_le_bytes([b[12], b[13], b[14], b[15]]),
            name,
        };
        let plausible = (1..=crate::MAX_JOINTS).contains(&usize::from(h.joint_count))
            && (1..=super::MAX_SLICES).contains(&h.slice_count);
        plausible.then_some(h)
    }

    /// The name up to the first NUL; `None` if those bytes are not printable text
    /// ([`printable_name`]).
    pub fn name_str(&self) -> Option<&str> {
        printable_name(&self.name)
    }
}

/// A stored gait name up to its first NUL, if it is printable text: UTF-8 without control
/// characters (a name holding an escape sequence would rewrite the user's terminal when shown).
/// `None` otherwise; every place that shows a name says so instead.
pub fn printable_name(name: &[u8]) -> Option<&str> {
    let end = name.iter().position(|&b| b == 0).unwrap_or(name.len());
    core::str::from_utf8(&name[..end])
        .ok()
        .filter(|s| !s.chars().any(char::is_control))
}

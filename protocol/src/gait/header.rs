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

    /// The name up to the first NUL; `None` if those bytes are not UTF-8.
    pub fn name_str(&self) -> Option<&str> {
        let end = self.name.iter().position(|&b| b == 0).unwrap_or(NAME_LEN);
        core::str::from_utf8(&self.name[..end]).ok()
    }
}

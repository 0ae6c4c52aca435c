//! What the gait store reports of a copy it found damaged at mount and did not use: its own file so
//! the device log can name it without importing the store that logs it.

/// Why [`GaitStore::mount`](super::GaitStore::mount) rejected a bank that was not erased.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LossReason {
    /// The commit record holds, but the table's bytes no longer have the CRC it names (`actual`).
    TableChecksum { actual: u32 },
    /// The commit record is neither erased nor readable (its magic, own CRC, slot, bank or length
    /// is wrong), so nothing about the copy can be trusted, not even whether it was the newer one.
    RecordDamaged,
}

/// A copy of a slot's table that [`GaitStore::mount`](super::GaitStore::mount) found damaged and did not use: either newer
/// than the current table (the slot fell back to an older gait) or of unknown age.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LostCopy {
    /// The bank it sits in.
    pub bank: u16,
    /// Sequence number, length and CRC from its commit record (`None` when the record is damaged).
    pub seq: Option<u32>,
    pub len: Option<u32>,
    pub crc: Option<u32>,
    pub reason: LossReason,
}

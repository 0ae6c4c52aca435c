//! Gait store: several slots of step tables in the reserved flash region, each slot with two banks
//! (A/B). A new table goes into the spare bank and becomes current only when its CRC has been checked
//! on the bytes in flash and a commit record with a higher sequence number has been written after it,
//! so a reset or power loss at any moment leaves the old table or the new one, never a broken one.
//! Tables are read in place through [`FlashWindow`] (XIP on the board), never copied to RAM.
//!
//! Bank layout: `[record: 32 B][0xFF up to 256 B][table bytes]`. The record is written last.

#[cfg(test)]
mod damage_tests;
pub mod lost;
#[cfg(any(test, feature = "std"))]
pub mod nor_double;
pub mod record;
#[cfg(test)]
mod tests;
mod upload;

use embedded_storage::nor_flash::{NorFlash, NorFlashError, NorFlashErrorKind};

pub use lost::{LossReason, LostCopy};
use record::{CRC32, HEADER, RECORD_LEN, Record};

/// Most slots a store can hold (the board uses [`BOARD_SLOTS`]).
pub const MAX_SLOTS: usize = 8;
/// Slots on the board: 4 slots x 2 banks x 192 KB fill the 1.5 MB region; a 22 x 1000 table needs
/// under 100 KB.
pub const BOARD_SLOTS: u8 = 4;
/// Bytes the record occupies in flash, padded so any write unit up to 32 B divides it.
const RECORD_SPAN: usize = 32;
/// Largest write unit the store supports (it keeps a tail of this size between chunks).
const MAX_WRITE: usize = 32;

/// The flash as the CPU reads it: on the board the XIP-mapped gait region, in tests the double's
/// memory. Slices borrow the store, and writes need `&mut`, so a table can never change under a reader.
pub trait FlashWindow {
    /// All bytes of the region, offset 0 = offset 0 of the [`NorFlash`] it belongs to.
    fn window(&self) -> &[u8];
}

/// Why the flash driver failed, without its driver-specific payload.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FlashFault {
    NotAligned,
    OutOfBounds,
    Other,
}

/// Errors of the gait store; every one leaves the slot's current table as it was.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum StoreError {
    /// The slot number is past the last slot.
    NoSuchSlot { slot: u8, slots: u8 },
    /// The table does not fit a bank (or is empty).
    BadSize { len: u32, max: u32 },
    /// A chunk or commit came without a begun upload.
    NoUpload,
    /// A chunk does not start where the previous one ended (reordered, duplicated or lost chunk).
    OutOfOrder { expected: u32, got: u32 },
    /// A chunk runs past the announced size.
    Overflow { offset: u32, len: u32, total: u32 },
    /// Commit before all announced bytes arrived.
    Incomplete { received: u32, total: u32 },
    /// The CRC of the bytes in flash is not the one announced.
    ChecksumMismatch { expected: u32, actual: u32 },
    /// What was read back after writing is not what was written.
    Verify { offset: u32 },
    /// The flash driver failed.
    Flash(FlashFault),
}

/// Why a verified commit failed: the store, or the caller's check of the table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CommitError<E> {
    Store(StoreError),
    Rejected(E),
}

/// A commit with no check of its own: every table the store takes is accepted.
pub(crate) fn accept_any(_: &[u8]) -> Result<(), core::convert::Infallible> {
    Ok(())
}

impl CommitError<core::convert::Infallible> {
    /// The store's error: an unchecked commit ([`accept_any`]) can fail only there.
    pub fn into_store(self) -> StoreError {
        match self {
            CommitError::Store(e) => e,
            CommitError::Rejected(never) => match never {},
        }
    }
}

impl<E> From<StoreError> for CommitError<E> {
    fn from(e: StoreError) -> Self {
        CommitError::Store(e)
    }
}

fn fault<E: NorFlashError>(e: E) -> StoreError {
    StoreError::Flash(match e.kind() {
        NorFlashErrorKind::NotAligned => FlashFault::NotAligned,
        NorFlashErrorKind::OutOfBounds => FlashFault::OutOfBounds,
        _ => FlashFault::Other,
    })
}

/// Summary of one slot, for listings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SlotInfo {
    pub slot: u8,
    pub len: u32,
    pub crc: u32,
    pub seq: u32,
}

/// What [`GaitStore::mount`] found in one bank.
enum Bank {
    Erased,
    Valid(Record),
    Damaged(LostCopy),
}

/// The gait store over a flash `F` that covers exactly the gait region.
#[derive(Debug)]
pub struct GaitStore<F> {
    flash: F,
    slots: u8,
    bank_size: u32,
    current: [Option<Record>; MAX_SLOTS],
    /// Per slot, the damaged copy found at mount that is newer than the current one (or of unknown
    /// age); cleared when an upload into the slot commits or the slot is deleted.
    lost: [Option<LostCopy>; MAX_SLOTS],
    upload: Option<upload::Upload>,
}

impl<F: NorFlash + FlashWindow> GaitStore<F> {
    /// Scans `flash` for committed banks: per slot the valid bank (record and table CRC hold) with the
    /// highest sequence number is current. Never writes, so mounting after a power loss is safe.
    pub fn mount(flash: F, slots: u8) -> Self {
        const { assert!(F::WRITE_SIZE <= MAX_WRITE && RECORD_SPAN.is_multiple_of(F::WRITE_SIZE)) };
        let slots = slots.clamp(1, MAX_SLOTS as u8);
        let bank = flash.capacity() / (2 * slots as usize);
        let bank_size = (bank - bank % F::ERASE_SIZE) as u32;
        let mut store = Self {
            flash,
            slots,
            bank_size,
            current: [None; MAX_SLOTS],
            lost: [None; MAX_SLOTS],
            upload: None,
        };
        for slot in 0..slots {
            let banks = [store.classify(slot, 0), store.classify(slot, 1)];
            let current = banks
                .iter()
                .filter_map(|b| match b {
                    Bank::Valid(r) => Some(*r),
                    _ => None,
                })
                .max_by_key(|r| r.seq);
            // A damaged copy matters when it was (or may have been) newer than what is current: an
            // older copy that rotted is the spare bank the next upload overwrites anyway.
            let lost = banks
                .iter()
                .filter_map(|b| match b {
                    Bank::Damaged(l) => Some(*l),
                    _ => None,
                })
                .filter(|l| match (l.seq, current) {
                    (Some(seq), Some(cur)) => seq > cur.seq,
                    _ => true,
                })
                .max_by_key(|l| l.seq.map_or(0, |s| u64::from(s) + 1));
            if let Some(l) = lost {
                crate::device_log::store_copy_lost(slot, l, current.map(|r| r.seq));
            }
            store.current[slot as usize] = current;
            store.lost[slot as usize] = lost;
        }
        store
    }

    /// The damaged copy of `slot` found at mount that was newer than the current table (the slot fell
    /// back) or of unknown age (the record is unreadable), until an upload into the slot commits.
    pub fn lost(&self, slot: u8) -> Option<LostCopy> {
        self.lost.get(slot as usize).copied().flatten()
    }

    /// The bytes of a lost copy's table as they sit in flash (its recorded length, or the whole bank
    /// past the header when the record is damaged): only for reading what is left of its header.
    pub fn lost_bytes(&self, slot: u8) -> Option<&[u8]> {
        let l = self.lost(slot)?;
        let start = self.bank_base(slot, l.bank) as usize + HEADER;
        let len = l.len.unwrap_or(self.max_table_len()) as usize;
        self.flash.window().get(start..start + len)
    }

    /// Whether mount found damaged data (a lost copy) in any slot, as opposed to erased banks.
    pub fn damaged(&self) -> bool {
        self.lost.iter().any(Option::is_some)
    }

    /// Number of slots.
    pub fn slots(&self) -> u8 {
        self.slots
    }

    /// Largest table a slot takes, in bytes.
    pub fn max_table_len(&self) -> u32 {
        self.bank_size - HEADER as u32
    }

    /// The current table of `slot`, read in place.
    pub fn table(&self, slot: u8) -> Option<&[u8]> {
        let r = self.current.get(slot as usize).copied().flatten()?;
        let start = self.bank_base(slot, r.bank) as usize + HEADER;
        self.flash.window().get(start..start + r.len as usize)
    }

    /// Length, CRC and sequence number of the current table of `slot`.
    pub fn info(&self, slot: u8) -> Option<SlotInfo> {
        let r = self.current.get(slot as usize).copied().flatten()?;
        Some(SlotInfo {
            slot,
            len: r.len,
            crc: r.crc,
            seq: r.seq,
        })
    }

    /// The slot an upload is going into, if any.
    pub fn upload_slot(&self) -> Option<u8> {
        self.upload.as_ref().map(|u| u.slot)
    }

    /// Gives the flash back (tests use this to cut the power and mount again).
    pub fn into_flash(self) -> F {
        self.flash
    }

    /// Empties `slot`: erases the record of the older bank first, then of the current one, so a power
    /// loss in between leaves the current table, never an older one brought back.
    pub fn delete(&mut self, slot: u8) -> Result<(), StoreError> {
        self.check_slot(slot)?;
        if self.upload.as_ref().is_some_and(|u| u.slot == slot) {
            self.upload = None;
        }
        let cur = self.current[slot as usize].map_or(0, |r| r.bank);
        for bank in [1 - cur, cur] {
            let base = self.bank_base(slot, bank);
            self.flash
                .erase(base, base + F::ERASE_SIZE as u32)
                .map_err(fault)?;
            if bank == cur {
                self.current[slot as usize] = None;
                self.lost[slot as usize] = None;
            }
        }
        Ok(())
    }

    fn check_slot(&self, slot: u8) -> Result<(), StoreError> {
        if slot >= self.slots {
            return Err(StoreError::NoSuchSlot {
                slot,
                slots: self.slots,
            });
        }
        Ok(())
    }

    fn bank_base(&self, slot: u8, bank: u16) -> u32 {
        (slot as u32 * 2 + bank as u32) * self.bank_size
    }

    /// The record of a bank if it is intact, belongs there, and the table it names has its CRC.
    fn valid_record(&self, slot: u8, bank: u16) -> Option<Record> {
        match self.classify(slot, bank) {
            Bank::Valid(r) => Some(r),
            _ => None,
        }
    }

    /// Whether the record area of a bank is still erased (nothing was ever committed there).
    fn record_erased(&self, slot: u8, bank: u16) -> bool {
        let base = self.bank_base(slot, bank) as usize;
        self.flash
            .window()
            .get(base..base + RECORD_LEN)
            .is_some_and(|b| b.iter().all(|&x| x == 0xFF))
    }

    /// What a bank holds: an erased record, a valid commit, or damaged data and why.
    fn classify(&self, slot: u8, bank: u16) -> Bank {
        if self.record_erased(slot, bank) {
            return Bank::Erased;
        }
        let damaged = Bank::Damaged(LostCopy {
            bank,
            seq: None,
            len: None,
            crc: None,
            reason: LossReason::RecordDamaged,
        });
        let base = self.bank_base(slot, bank) as usize;
        let window = self.flash.window();
        let Some(r) = window.get(base..base + RECORD_LEN).and_then(Record::decode) else {
            return damaged;
        };
        if r.slot != slot as u16 || r.bank != bank || r.len == 0 || r.len > self.max_table_len() {
            return damaged;
        }
        let Some(table) = window.get(base + HEADER..base + HEADER + r.len as usize) else {
            return damaged;
        };
        let actual = CRC32.checksum(table);
        if actual == r.crc {
            Bank::Valid(r)
        } else {
            Bank::Damaged(LostCopy {
                bank,
                seq: Some(r.seq),
                len: Some(r.len),
                crc: Some(r.crc),
                reason: LossReason::TableChecksum { actual },
            })
        }
    }
}

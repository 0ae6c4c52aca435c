//! Gait store: several slots of step tables in the reserved flash region, each slot with two banks
//! (A/B). A new table goes into the spare bank and becomes current only when its CRC has been checked
//! on the bytes in flash and a commit record with a higher sequence number has been written after it,
//! so a reset or power loss at any moment leaves the old table or the new one, never a broken one.
//! Tables are read in place through [`FlashWindow`] (XIP on the board), never copied to RAM.
//!
//! Bank layout: `[record: 32 B][0xFF up to 256 B][table bytes]`. The record is written last.

#[cfg(any(test, feature = "std"))]
pub mod nor_double;
pub mod record;
#[cfg(test)]
mod tests;

use embedded_storage::nor_flash::{NorFlash, NorFlashError, NorFlashErrorKind};

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

/// An upload in progress into the spare bank of a slot.
#[derive(Debug, Clone)]
struct Upload {
    slot: u8,
    bank: u16,
    seq: u32,
    total: u32,
    /// Bytes already programmed into flash (a multiple of the write unit).
    flushed: u32,
    /// Received bytes that do not fill a write unit yet.
    tail: [u8; MAX_WRITE],
    tail_len: usize,
    /// Bytes of the bank (from its start) erased so far; sectors are erased as chunks reach them,
    /// so no request blocks for more than one sector erase (tens of ms) beyond its writes.
    erased: u32,
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

/// The gait store over a flash `F` that covers exactly the gait region.
#[derive(Debug)]
pub struct GaitStore<F> {
    flash: F,
    slots: u8,
    bank_size: u32,
    current: [Option<Record>; MAX_SLOTS],
    upload: Option<Upload>,
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
            upload: None,
        };
        for slot in 0..slots {
            store.current[slot as usize] = (0..2)
                .filter_map(|bank| store.valid_record(slot, bank))
                .max_by_key(|r| r.seq);
        }
        store
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

    /// Starts replacing the table of `slot` with `total` bytes: erases the first sector of the spare
    /// bank (its record, so the bank is invalid from here on); later sectors are erased as chunks
    /// reach them. Any upload in progress is abandoned (its bank was never committed).
    pub fn begin(&mut self, slot: u8, total: u32) -> Result<(), StoreError> {
        self.check_slot(slot)?;
        if total == 0 || total > self.max_table_len() {
            return Err(StoreError::BadSize {
                len: total,
                max: self.max_table_len(),
            });
        }
        self.upload = None;
        let cur = self.current[slot as usize];
        let bank = cur.map_or(0, |r| 1 - r.bank);
        let seq = cur.map_or(1, |r| r.seq.wrapping_add(1));
        let base = self.bank_base(slot, bank);
        // The record sits in the first sector, so the bank stops being valid with the first erase.
        self.flash
            .erase(base, base + F::ERASE_SIZE as u32)
            .map_err(fault)?;
        self.upload = Some(Upload {
            slot,
            bank,
            seq,
            total,
            flushed: 0,
            tail: [0xFF; MAX_WRITE],
            tail_len: 0,
            erased: F::ERASE_SIZE as u32,
        });
        Ok(())
    }

    /// Appends `data` at `offset` of the table being uploaded. Chunks must come in order and without
    /// gaps: NOR cannot rewrite, so a reordered or repeated chunk is refused, not merged.
    /// A flash failure ends the upload (what reached the bank is unknown); a refused chunk does not.
    pub fn write(&mut self, offset: u32, data: &[u8]) -> Result<(), StoreError> {
        let result = self.append(offset, data);
        if let Err(StoreError::Flash(_)) = result {
            self.upload = None;
        }
        result
    }

    fn append(&mut self, offset: u32, data: &[u8]) -> Result<(), StoreError> {
        let u = self.upload.as_ref().ok_or(StoreError::NoUpload)?;
        let base = self.bank_base(u.slot, u.bank) + HEADER as u32;
        let received = u.flushed + u.tail_len as u32;
        if offset != received {
            return Err(StoreError::OutOfOrder {
                expected: received,
                got: offset,
            });
        }
        let len = data.len() as u32;
        if len > u.total - received {
            return Err(StoreError::Overflow {
                offset,
                len,
                total: u.total,
            });
        }
        let w = F::WRITE_SIZE;
        // Everything this chunk can program lies below the bank offset of its end, rounded up to a
        // write unit.
        let end = HEADER as u32 + (received + len).div_ceil(w as u32) * w as u32;
        self.erase_to(end)?;
        let u = self.upload.as_mut().ok_or(StoreError::NoUpload)?;
        let mut data = data;
        if u.tail_len > 0 {
            let n = (w - u.tail_len).min(data.len());
            u.tail[u.tail_len..u.tail_len + n].copy_from_slice(&data[..n]);
            u.tail_len += n;
            data = &data[n..];
            if u.tail_len == w {
                self.flash
                    .write(base + u.flushed, &u.tail[..w])
                    .map_err(fault)?;
                u.flushed += w as u32;
                u.tail = [0xFF; MAX_WRITE];
                u.tail_len = 0;
            }
        }
        let whole = data.len() - data.len() % w;
        if whole > 0 {
            self.flash
                .write(base + u.flushed, &data[..whole])
                .map_err(fault)?;
            u.flushed += whole as u32;
        }
        let rest = &data[whole..];
        u.tail[u.tail_len..u.tail_len + rest.len()].copy_from_slice(rest);
        u.tail_len += rest.len();
        Ok(())
    }

    /// Checks that all bytes arrived and that the CRC-32 of what is in flash is `crc`, then writes the
    /// commit record: from then on the new table is current. On any error the old table stays current
    /// and the upload is over.
    pub fn commit(&mut self, crc: u32) -> Result<SlotInfo, StoreError> {
        self.commit_verified(crc, |_| Ok::<(), core::convert::Infallible>(()))
            .map_err(|e| match e {
                CommitError::Store(e) => e,
                CommitError::Rejected(never) => match never {},
            })
    }

    /// As [`GaitStore::commit`], and `verify` must also accept the table's bytes as they sit in flash
    /// before the record makes them current (the link checks the table format there).
    pub fn commit_verified<E>(
        &mut self,
        crc: u32,
        verify: impl FnOnce(&[u8]) -> Result<(), E>,
    ) -> Result<SlotInfo, CommitError<E>> {
        let u = self.upload.take().ok_or(StoreError::NoUpload)?;
        let received = u.flushed + u.tail_len as u32;
        if received != u.total {
            return Err(StoreError::Incomplete {
                received,
                total: u.total,
            }
            .into());
        }
        let bank_base = self.bank_base(u.slot, u.bank);
        let base = bank_base + HEADER as u32;
        if u.tail_len > 0 {
            // The padding is 0xFF, which programs nothing.
            self.flash
                .write(base + u.flushed, &u.tail[..F::WRITE_SIZE])
                .map_err(fault)?;
        }
        let start = base as usize;
        let actual = CRC32.checksum(&self.flash.window()[start..start + u.total as usize]);
        if actual != crc {
            return Err(StoreError::ChecksumMismatch {
                expected: crc,
                actual,
            }
            .into());
        }
        verify(&self.flash.window()[start..start + u.total as usize])
            .map_err(CommitError::Rejected)?;
        let record = Record {
            slot: u.slot as u16,
            bank: u.bank,
            seq: u.seq,
            len: u.total,
            crc,
        };
        let mut bytes = [0xFF; RECORD_SPAN];
        bytes[..RECORD_LEN].copy_from_slice(&record.encode());
        self.flash.write(bank_base, &bytes).map_err(fault)?;
        if self.valid_record(u.slot, u.bank) != Some(record) {
            return Err(StoreError::Verify { offset: bank_base }.into());
        }
        self.current[u.slot as usize] = Some(record);
        Ok(SlotInfo {
            slot: u.slot,
            len: u.total,
            crc,
            seq: u.seq,
        })
    }

    /// Abandons the upload in progress; the slot keeps its current table.
    pub fn abort(&mut self) {
        self.upload = None;
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
            }
        }
        Ok(())
    }

    /// Erases the upload's bank up to `end` (bank-relative), sector by sector.
    fn erase_to(&mut self, end: u32) -> Result<(), StoreError> {
        let Some(u) = self.upload.as_ref() else {
            return Err(StoreError::NoUpload);
        };
        let base = self.bank_base(u.slot, u.bank);
        let mut erased = u.erased;
        while erased < end {
            let at = base + erased;
            self.flash
                .erase(at, at + F::ERASE_SIZE as u32)
                .map_err(fault)?;
            erased += F::ERASE_SIZE as u32;
            if let Some(u) = self.upload.as_mut() {
                u.erased = erased;
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
        let base = self.bank_base(slot, bank) as usize;
        let window = self.flash.window();
        let r = Record::decode(window.get(base..base + RECORD_LEN)?)?;
        if r.slot != slot as u16 || r.bank != bank || r.len == 0 || r.len > self.max_table_len() {
            return None;
        }
        let table = window.get(base + HEADER..base + HEADER + r.len as usize)?;
        (CRC32.checksum(table) == r.crc).then_some(r)
    }
}

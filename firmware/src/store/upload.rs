//! Uploads into a slot's spare bank: erase as chunks arrive, program in write units, check the CRC
//! (and the caller's format check) on the bytes in flash, then write the commit record.

use embedded_storage::nor_flash::NorFlash;

use super::record::{CRC32, HEADER, RECORD_LEN, Record};
use super::{
    CommitError, FlashWindow, GaitStore, MAX_WRITE, RECORD_SPAN, SlotInfo, StoreError, fault,
};

/// An upload in progress into the spare bank of a slot.
#[derive(Debug, Clone)]
pub(super) struct Upload {
    pub(super) slot: u8,
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

impl<F: NorFlash + FlashWindow> GaitStore<F> {
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
        // A slot with no valid copy may hold damage in its other bank too: erase that record as well,
        // so the mark of a lost copy does not come back at the next mount once this upload commits.
        let other = 1 - bank;
        if cur.is_none() && !self.record_erased(slot, other) {
            let at = self.bank_base(slot, other);
            self.flash
                .erase(at, at + F::ERASE_SIZE as u32)
                .map_err(fault)?;
        }
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
        self.commit_verified(crc, super::accept_any)
            .map_err(CommitError::into_store)
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
        self.lost[u.slot as usize] = None;
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
}

//! Uploading a gait table: begin, chunks in order, commit with the CRC, then read the slot back to
//! verify. Any failure midway aborts the upload (best effort) so the slot keeps its old table.
//! Only a [`CheckedTable`] is uploaded: the rules (`crate::rules::build`) are the one maker of it,
//! so no door can send a table the rules have not seen.

use protocol::endpoint as ep;
use protocol::{GaitSummary, GaitTable};

use super::board::Board;
use super::error::LinkError;
use super::transport::Transport;
use crate::rules::build::CheckedTable;

/// What an upload did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UploadReport {
    pub slot: u8,
    /// What the slot held before (`None`: it was empty).
    pub replaced: Option<GaitSummary>,
    /// What it holds now, as the board reports it after the upload.
    pub stored: GaitSummary,
    /// Table bytes sent and chunks used.
    pub bytes: u32,
    pub chunks: u32,
}

/// Shorthand for the result of [`Board::upload`].
pub type Uploaded = Result<UploadReport, LinkError>;

impl<T: Transport> Board<T> {
    /// Uploads `table` into `slot`, calling `progress(sent, total)` after every chunk, and verifies
    /// the slot afterwards (header and CRC as listed by the board).
    pub fn upload(
        &mut self,
        slot: u8,
        table: &CheckedTable,
        progress: impl FnMut(u32, u32),
    ) -> Uploaded {
        self.upload_unless(slot, table, progress, || false)
    }

    /// [`Board::upload`] that gives up before the next chunk once `interrupted()` is true (a
    /// Ctrl-C): the upload is aborted, the slot keeps its old table, and the error is
    /// [`LinkError::UploadInterrupted`]. It is asked again after the last chunk, before the
    /// commit; once the commit is sent the upload runs to its end.
    pub fn upload_unless(
        &mut self,
        slot: u8,
        table: &CheckedTable,
        mut progress: impl FnMut(u32, u32),
        mut interrupted: impl FnMut() -> bool,
    ) -> Uploaded {
        let table = table.bytes();
        let parsed = GaitTable::parse(table).map_err(LinkError::Table)?;
        let header = parsed.header();
        let total_len = table.len() as u32;
        let replaced = self
            .gaits()?
            .into_iter()
            .find(|s| s.slot == slot)
            .and_then(|s| s.gait);
        self.call(ep::UploadBegin {
            slot,
            header,
            total_len,
        })?;
        let result = self
            .send_chunks(slot, table, &mut progress, &mut interrupted)
            .and_then(|chunks| {
                // A Ctrl-C after the last chunk still lands before the commit: nothing is stored.
                if interrupted() {
                    return Err(LinkError::UploadInterrupted {
                        port: self.port().to_owned(),
                        slot,
                        sent: total_len,
                        total: total_len,
                    });
                }
                Ok(chunks)
            });
        let chunks = match result {
            Ok(chunks) => chunks,
            Err(e) => {
                if !e.is_vanished() {
                    // Leaves the slot as it was; if even this fails the board drops the unfinished
                    // upload at the next UploadBegin anyway.
                    let _ = self.call(ep::UploadAbort);
                }
                return Err(e);
            }
        };
        let port = self.port().to_owned();
        let crc = protocol::crc32::checksum(table);
        match self.call(ep::UploadCommit { crc })? {
            ep::Committed { slot: s, crc: c } if s == slot && c == crc => {}
            other => {
                return Err(LinkError::Verify {
                    port,
                    what: format!(
                        "commit answered {other:?}, expected slot {slot} CRC {crc:#010x}"
                    ),
                });
            }
        }
        let stored = self
            .gaits()?
            .into_iter()
            .find(|s| s.slot == slot)
            .and_then(|s| s.gait)
            .ok_or_else(|| LinkError::Verify {
                port: port.clone(),
                what: format!("slot {slot} is empty after the upload"),
            })?;
        if stored.header != header || stored.crc != parsed.crc() {
            return Err(LinkError::Verify {
                port,
                what: format!(
                    "slot {slot} holds {:?} (CRC {:#010x}), expected {:?} (CRC {:#010x})",
                    stored.header,
                    stored.crc,
                    header,
                    parsed.crc()
                ),
            });
        }
        Ok(UploadReport {
            slot,
            replaced,
            stored,
            bytes: total_len,
            chunks,
        })
    }

    fn send_chunks(
        &mut self,
        slot: u8,
        table: &[u8],
        progress: &mut impl FnMut(u32, u32),
        interrupted: &mut impl FnMut() -> bool,
    ) -> Result<u32, LinkError> {
        let max = usize::from(self.info().max_chunk_len).clamp(1, protocol::MAX_CHUNK_LEN);
        let total = table.len() as u32;
        let mut chunks = 0;
        for (i, piece) in table.chunks(max).enumerate() {
            let offset = (i * max) as u32;
            if interrupted() {
                return Err(LinkError::UploadInterrupted {
                    port: self.port().to_owned(),
                    slot,
                    sent: offset,
                    total,
                });
            }
            let data = heapless::Vec::from_slice(piece).expect("chunk is at most MAX_CHUNK_LEN");
            let expect = offset + piece.len() as u32;
            match self.call(ep::UploadChunk { offset, data })? {
                ep::ChunkAccepted { received } if received == expect => {}
                other => {
                    return Err(LinkError::Verify {
                        port: self.port().to_owned(),
                        what: format!(
                            "chunk at {offset} answered {other:?}, expected {expect} bytes received"
                        ),
                    });
                }
            }
            chunks += 1;
            progress(expect, total);
        }
        Ok(chunks)
    }
}

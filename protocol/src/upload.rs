//! [`UploadTracker`]: the pure state machine that decides what happens to each upload step.
//!
//! The firmware's gait store owns the flash; it asks the tracker first and writes only what the
//! tracker accepted, so the board and the host tests share one set of rules:
//!
//! * chunks arrive in order without gaps: a chunk at `offset < received` is a [`UploadError::Duplicate`]
//!   (e.g. a retransmission after a lost reply), one at `offset > received` is
//!   [`UploadError::OutOfOrder`]; neither changes anything, the host resumes at `received`;
//! * a chunk longer than [`MAX_CHUNK_LEN`] is [`UploadError::ChunkTooLong`], one reaching past the
//!   announced length [`UploadError::PastEnd`], an empty one [`UploadError::EmptyChunk`];
//! * commit before every byte arrived is [`UploadError::Truncated`] (the upload stays open);
//! * a commit CRC that disagrees with the CRC of the bytes received is [`UploadError::ChecksumMismatch`]
//!   and discards the upload (its bytes are wrong somewhere);
//! * after a successful commit the store re-reads what it wrote, checks it with [`verify_stored`],
//!   and only then makes the slot current. Until then the slot's previous table stays untouched.

use core::fmt;

use crate::gait::{GaitHeader, GaitTable, MAX_SLICES, TableError};
use crate::message::UploadProgress;
use crate::{MAX_CHUNK_LEN, MAX_JOINTS, crc32};

/// Why an upload step was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum UploadError {
    /// Chunk, commit or abort without an upload in progress.
    NotStarted,
    /// The slot does not exist.
    NoSuchSlot { slot: u8, slots: u8 },
    /// The announced header is not a valid table shape.
    BadHeader(TableError),
    /// `total_len` disagrees with the length the header implies.
    LengthMismatch { total_len: u32, expected: u32 },
    /// The table does not fit a slot.
    TooLarge { total_len: u32, capacity: u32 },
    /// A chunk without data.
    EmptyChunk { offset: u32 },
    /// A chunk longer than [`MAX_CHUNK_LEN`].
    ChunkTooLong { offset: u32, len: u32, max: u32 },
    /// A chunk reaching past the announced length.
    PastEnd {
        offset: u32,
        len: u32,
        total_len: u32,
    },
    /// A chunk starting before the next expected byte: already received.
    Duplicate { offset: u32, received: u32 },
    /// A chunk starting after the next expected byte: one went missing or chunks were reordered.
    OutOfOrder { offset: u32, expected: u32 },
    /// Commit before the whole table arrived.
    Truncated { received: u32, total_len: u32 },
    /// The commit CRC disagrees with the bytes received; the upload is discarded.
    ChecksumMismatch { expected: u32, computed: u32 },
    /// The stored bytes are not a valid table.
    Table(TableError),
    /// The stored table's header differs from the one announced at begin.
    HeaderMismatch,
}

impl fmt::Display for UploadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotStarted => write!(f, "no upload in progress"),
            Self::NoSuchSlot { slot, slots } => {
                write!(f, "no gait slot {slot} (board has {slots})")
            }
            Self::BadHeader(e) => write!(f, "announced header invalid: {e}"),
            Self::LengthMismatch {
                total_len,
                expected,
            } => {
                write!(
                    f,
                    "announced {total_len} bytes, the header implies {expected}"
                )
            }
            Self::TooLarge {
                total_len,
                capacity,
            } => {
                write!(
                    f,
                    "table of {total_len} bytes does not fit a slot of {capacity}"
                )
            }
            Self::EmptyChunk { offset } => write!(f, "empty chunk at offset {offset}"),
            Self::ChunkTooLong { offset, len, max } => {
                write!(f, "chunk at offset {offset} of {len} bytes, at most {max}")
            }
            Self::PastEnd {
                offset,
                len,
                total_len,
            } => {
                write!(
                    f,
                    "chunk at offset {offset} of {len} bytes passes the end ({total_len})"
                )
            }
            Self::Duplicate { offset, received } => {
                write!(
                    f,
                    "chunk at offset {offset} already received (have {received} bytes)"
                )
            }
            Self::OutOfOrder { offset, expected } => {
                write!(
                    f,
                    "chunk at offset {offset} out of order, expected offset {expected}"
                )
            }
            Self::Truncated {
                received,
                total_len,
            } => {
                write!(f, "commit after {received} of {total_len} bytes")
            }
            Self::ChecksumMismatch { expected, computed } => {
                write!(
                    f,
                    "commit CRC {expected:#010x}, received bytes give {computed:#010x}"
                )
            }
            Self::Table(e) => write!(f, "stored table invalid: {e}"),
            Self::HeaderMismatch => {
                write!(f, "stored table's header differs from the announced one")
            }
        }
    }
}

impl core::error::Error for UploadError {}

/// What the board can take.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct UploadLimits {
    /// Number of slots (slots are `0..slots`).
    pub slots: u8,
    /// Bytes a slot holds.
    pub slot_capacity: u32,
}

/// An upload whose bytes all arrived with the right CRC: write-complete, to be verified.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Finished {
    pub slot: u8,
    pub header: GaitHeader,
    pub total_len: u32,
    pub crc: u32,
}

#[derive(Clone)]
struct Active {
    slot: u8,
    header: GaitHeader,
    total_len: u32,
    received: u32,
    crc: crc32::Digest,
}

/// The upload state machine (see the module docs).
#[derive(Clone, Default)]
pub struct UploadTracker {
    active: Option<Active>,
}

impl fmt::Debug for UploadTracker {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("UploadTracker")
            .field("progress", &self.progress())
            .finish()
    }
}

impl UploadTracker {
    /// No upload in progress.
    pub const fn new() -> Self {
        Self { active: None }
    }

    /// The upload in progress, if any.
    pub fn progress(&self) -> Option<UploadProgress> {
        self.active.as_ref().map(|a| UploadProgress {
            slot: a.slot,
            received: a.received,
            total_len: a.total_len,
        })
    }

    /// Starts an upload, replacing an unfinished one. On error the previous state is kept.
    pub fn begin(
        &mut self,
        slot: u8,
        header: &GaitHeader,
        total_len: u32,
        limits: &UploadLimits,
    ) -> Result<(), UploadError> {
        if slot >= limits.slots {
            return Err(UploadError::NoSuchSlot {
                slot,
                slots: limits.slots,
            });
        }
        check_header(header).map_err(UploadError::BadHeader)?;
        let expected = header.table_len();
        if total_len != expected {
            return Err(UploadError::LengthMismatch {
                total_len,
                expected,
            });
        }
        if total_len > limits.slot_capacity {
            return Err(UploadError::TooLarge {
                total_len,
                capacity: limits.slot_capacity,
            });
        }
        self.active = Some(Active {
            slot,
            header: *header,
            total_len,
            received: 0,
            crc: crc32::digest(),
        });
        Ok(())
    }

    /// Decides on a chunk; on `Ok` the store writes `data` at `offset`. Returns the bytes received.
    pub fn chunk(&mut self, offset: u32, data: &[u8]) -> Result<u32, UploadError> {
        let a = self.active.as_mut().ok_or(UploadError::NotStarted)?;
        let len = u32::try_from(data.len()).unwrap_or(u32::MAX);
        if data.is_empty() {
            return Err(UploadError::EmptyChunk { offset });
        }
        if data.len() > MAX_CHUNK_LEN {
            return Err(UploadError::ChunkTooLong {
                offset,
                len,
                max: MAX_CHUNK_LEN as u32,
            });
        }
        if offset.checked_add(len).is_none_or(|end| end > a.total_len) {
            return Err(UploadError::PastEnd {
                offset,
                len,
                total_len: a.total_len,
            });
        }
        if offset < a.received {
            return Err(UploadError::Duplicate {
                offset,
                received: a.received,
            });
        }
        if offset > a.received {
            return Err(UploadError::OutOfOrder {
                offset,
                expected: a.received,
            });
        }
        a.crc.update(data);
        a.received += len;
        Ok(a.received)
    }

    /// Ends the upload if every byte arrived and `crc` matches them.
    pub fn commit(&mut self, crc: u32) -> Result<Finished, UploadError> {
        let a = self.active.as_ref().ok_or(UploadError::NotStarted)?;
        if a.received < a.total_len {
            return Err(UploadError::Truncated {
                received: a.received,
                total_len: a.total_len,
            });
        }
        let computed = a.crc.clone().finalize();
        let finished = Finished {
            slot: a.slot,
            header: a.header,
            total_len: a.total_len,
            crc: computed,
        };
        self.active = None;
        if computed != crc {
            return Err(UploadError::ChecksumMismatch {
                expected: crc,
                computed,
            });
        }
        Ok(finished)
    }

    /// Drops the upload in progress; returns its slot.
    pub fn abort(&mut self) -> Result<u8, UploadError> {
        self.active
            .take()
            .map(|a| a.slot)
            .ok_or(UploadError::NotStarted)
    }
}

/// Checks the bytes the store wrote for a finished upload: a valid table, the announced header,
/// the committed CRC. Only then may the slot switch to it.
pub fn verify_stored<'a>(
    finished: &Finished,
    stored: &'a [u8],
) -> Result<GaitTable<'a>, UploadError> {
    let table = GaitTable::parse(stored).map_err(UploadError::Table)?;
    if table.header() != finished.header {
        return Err(UploadError::HeaderMismatch);
    }
    let computed = crc32::checksum(table.as_bytes());
    if computed != finished.crc {
        return Err(UploadError::ChecksumMismatch {
            expected: finished.crc,
            computed,
        });
    }
    Ok(table)
}

fn check_header(h: &GaitHeader) -> Result<(), TableError> {
    if h.joint_count == 0 || usize::from(h.joint_count) > MAX_JOINTS {
        return Err(TableError::BadJointCount {
            count: h.joint_count,
        });
    }
    if h.slice_count == 0 || h.slice_count > MAX_SLICES {
        return Err(TableError::BadSliceCount {
            count: h.slice_count,
        });
    }
    if h.duty == 0 || h.duty >= 10_000 {
        return Err(TableError::BadDuty { duty: h.duty });
    }
    if h.step_period_us == 0 {
        return Err(TableError::BadPeriod);
    }
    Ok(())
}

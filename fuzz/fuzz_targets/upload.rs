//! The upload tracker under any sequence of steps: never panics, never accepts a byte out of order,
//! and commits only when every byte arrived with the CRC the host announced.
#![no_main]

use libfuzzer_sys::fuzz_target;
use protocol::{GaitHeader, MAX_CHUNK_LEN, UploadLimits, UploadTracker};

fuzz_target!(|data: &[u8]| {
    let limits = UploadLimits { slots: 4, slot_capacity: 8 * 1024 };
    let mut tracker = UploadTracker::new();
    // The bytes the tracker accepted, in the order it accepted them.
    let mut accepted: Vec<u8> = Vec::new();
    let mut total = 0u32;
    let mut ops = data.chunks(8);
    while let Some(op) = ops.next() {
        let mut b = [0u8; 8];
        b[..op.len()].copy_from_slice(op);
        let word = u32::from_le_bytes([b[4], b[5], b[6], b[7]]);
        match b[0] % 5 {
            0 => {
                let header = GaitHeader {
                    joint_count: b[1] % 34,
                    slice_count: u16::from(b[2] % 40),
                    step_period_us: word,
                    duty: u16::from(b[3]) * 40,
                    name: [0; 16],
                };
                let len = if b[1] & 0x80 == 0 { header.table_len() } else { word };
                if tracker.begin(b[1] % 5, &header, len, &limits).is_ok() {
                    accepted.clear();
                    total = len;
                }
            }
            1 => {
                let offset = if b[1] & 1 == 0 { accepted.len() as u32 } else { word % 9000 };
                let len = usize::from(u16::from_le_bytes([b[2], b[3]])) % (MAX_CHUNK_LEN + 8);
                let chunk: Vec<u8> = (0..len).map(|i| (i as u8).wrapping_mul(b[1])).collect();
                let before = accepted.len() as u32;
                if let Ok(received) = tracker.chunk(offset, &chunk) {
                    assert_eq!(offset, before, "accepted a chunk out of order");
                    assert!(!chunk.is_empty() && chunk.len() <= MAX_CHUNK_LEN);
                    accepted.extend_from_slice(&chunk);
                    assert_eq!(received, accepted.len() as u32);
                    assert!(received <= total);
                }
            }
            2 => {
                let crc = if b[1] & 1 == 0 { protocol::crc32::checksum(&accepted) } else { word };
                if let Ok(done) = tracker.commit(crc) {
                    assert_eq!(accepted.len() as u32, total);
                    assert_eq!(done.crc, protocol::crc32::checksum(&accepted));
                    assert_eq!(done.crc, crc);
                }
            }
            3 => {
                let _ = tracker.abort();
            }
            _ => {
                let _ = tracker.progress();
            }
        }
    }
});

//! The upload state machine: truncated, reordered, duplicated and oversized chunks and a wrong
//! checksum each get their own error, and a refused step changes nothing. The firmware's gait store
//! runs the same tracker; `a_slot_keeps_its_old_table_...` models how it must use it (the store's own
//! power-loss tests live in the firmware crate).

use protocol::gait::TableError;
use protocol::upload::{Finished, verify_stored};
use protocol::*;

const LIMITS: UploadLimits = UploadLimits {
    slots: 4,
    slot_capacity: 100 * 1024,
};

/// A 22-joint, 30-slice table: 36 + 352 + 30 * 90 + 4 = 3092 bytes, seven chunks of 512 and one of 20.
fn table(seed: f64) -> Vec<u8> {
    let joints = (0..22)
        .map(|j| JointSpec {
            name: format!("J{j}"),
            servo_id: j + 1,
            model: if j % 4 == 3 {
                ServoModel::Mx64
            } else {
                ServoModel::Mx28
            },
            sign: Sign::Positive,
            zero_offset: 2048,
            min_rad: -2.0,
            max_rad: 2.0,
            stiffness_nm_per_rad: 8.4,
            leg: None,
        })
        .collect();
    let mut b = GaitTableBuilder::new("upload", 1.2, 0.6, joints);
    for s in 0..30 {
        let a: Vec<f64> = (0..22)
            .map(|j| (seed + f64::from(s * 22 + j) * 0.01).sin())
            .collect();
        b.slice(0b0101_0101 & 0x3F, &a, &a);
    }
    let t = b.build().unwrap();
    assert_eq!(t.len(), 3092);
    t
}

fn begin(tracker: &mut UploadTracker, t: &[u8]) {
    let h = GaitTable::parse(t).unwrap().header();
    tracker.begin(1, &h, t.len() as u32, &LIMITS).unwrap();
}

fn send_all(tracker: &mut UploadTracker, t: &[u8]) {
    send(tracker, t, 0..t.len());
}

/// Sends `t[range]` at its offsets in chunks of `MAX_CHUNK_LEN`, each accepted; the bytes
/// received after the last.
fn send(tracker: &mut UploadTracker, t: &[u8], range: std::ops::Range<usize>) -> u32 {
    let mut received = 0;
    for (i, chunk) in t[range.clone()].chunks(MAX_CHUNK_LEN).enumerate() {
        received = tracker
            .chunk((range.start + i * MAX_CHUNK_LEN) as u32, chunk)
            .unwrap();
    }
    received
}

#[test]
fn an_upload_in_order_commits_and_verifies() {
    let t = table(0.0);
    let mut tr = UploadTracker::new();
    begin(&mut tr, &t);
    assert_eq!(send(&mut tr, &t, 0..t.len()), 3092);
    let crc = protocol::crc32::checksum(&t);
    let done = tr.commit(crc).unwrap();
    assert_eq!((done.slot, done.total_len, done.crc), (1, 3092, crc));
    assert_eq!(tr.progress(), None);
    let table = verify_stored(&done, &t).unwrap();
    assert_eq!(table.as_bytes(), &t[..]);
}

#[test]
fn a_truncated_upload_cannot_commit_and_stays_open() {
    let t = table(0.0);
    let mut tr = UploadTracker::new();
    begin(&mut tr, &t);
    tr.chunk(0, &t[..512]).unwrap();
    let crc = protocol::crc32::checksum(&t);
    assert_eq!(
        tr.commit(crc),
        Err(UploadError::Truncated {
            received: 512,
            total_len: 3092
        })
    );
    assert_eq!(
        tr.progress(),
        Some(UploadProgress {
            slot: 1,
            received: 512,
            total_len: 3092
        })
    );
    send(&mut tr, &t, 512..t.len());
    assert!(tr.commit(crc).is_ok());
}

#[test]
fn reordered_and_duplicated_chunks_are_refused_without_effect() {
    let t = table(0.0);
    let mut tr = UploadTracker::new();
    begin(&mut tr, &t);
    // Chunk 1 overtakes chunk 0.
    assert_eq!(
        tr.chunk(512, &t[512..1024]),
        Err(UploadError::OutOfOrder {
            offset: 512,
            expected: 0
        })
    );
    assert_eq!(tr.progress().unwrap().received, 0);
    tr.chunk(0, &t[..512]).unwrap();
    // Chunk 0 again (a retransmission after a lost reply).
    assert_eq!(
        tr.chunk(0, &t[..512]),
        Err(UploadError::Duplicate {
            offset: 0,
            received: 512
        })
    );
    // A chunk overlapping what arrived is a duplicate too.
    assert_eq!(
        tr.chunk(256, &t[256..768]),
        Err(UploadError::Duplicate {
            offset: 256,
            received: 512
        })
    );
    assert_eq!(tr.progress().unwrap().received, 512);
    // The rest in order still gives the right CRC: the refused chunks left no trace.
    send(&mut tr, &t, 512..t.len());
    assert!(tr.commit(protocol::crc32::checksum(&t)).is_ok());
}

#[test]
fn oversized_chunks_and_tables_are_refused() {
    let t = table(0.0);
    let mut tr = UploadTracker::new();
    begin(&mut tr, &t);
    assert_eq!(
        tr.chunk(0, &t[..MAX_CHUNK_LEN + 1]),
        Err(UploadError::ChunkTooLong {
            offset: 0,
            len: 513,
            max: 512
        })
    );
    assert_eq!(tr.chunk(0, &[]), Err(UploadError::EmptyChunk { offset: 0 }));
    send(&mut tr, &t, 0..3072);
    // 21 bytes at 3072 reach one byte past the 3092-byte table.
    assert_eq!(
        tr.chunk(3072, &[0; 21]),
        Err(UploadError::PastEnd {
            offset: 3072,
            len: 21,
            total_len: 3092
        })
    );
    assert_eq!(
        tr.chunk(u32::MAX, &[0; 2]),
        Err(UploadError::PastEnd {
            offset: u32::MAX,
            len: 2,
            total_len: 3092
        })
    );

    let h = GaitTable::parse(&t).unwrap().header();
    let small = UploadLimits {
        slots: 4,
        slot_capacity: 3091,
    };
    assert_eq!(
        UploadTracker::new().begin(0, &h, 3092, &small),
        Err(UploadError::TooLarge {
            total_len: 3092,
            capacity: 3091
        })
    );
    assert_eq!(
        UploadTracker::new().begin(0, &h, 4000, &LIMITS),
        Err(UploadError::LengthMismatch {
            total_len: 4000,
            expected: 3092
        })
    );
    assert_eq!(
        UploadTracker::new().begin(4, &h, 3092, &LIMITS),
        Err(UploadError::NoSuchSlot { slot: 4, slots: 4 })
    );
    let mut bad = h;
    bad.duty = 0;
    assert_eq!(
        UploadTracker::new().begin(0, &bad, 3092, &LIMITS),
        Err(UploadError::BadHeader(TableError::BadDuty { duty: 0 }))
    );
}

#[test]
fn a_wrong_checksum_discards_the_upload() {
    let t = table(0.0);
    let mut tr = UploadTracker::new();
    begin(&mut tr, &t);
    send_all(&mut tr, &t);
    let crc = protocol::crc32::checksum(&t);
    assert_eq!(
        tr.commit(crc ^ 1),
        Err(UploadError::ChecksumMismatch {
            expected: crc ^ 1,
            computed: crc
        })
    );
    assert_eq!(tr.progress(), None);
    assert_eq!(tr.chunk(0, &t[..512]), Err(UploadError::NotStarted));
    assert_eq!(tr.commit(crc), Err(UploadError::NotStarted));
}

#[test]
fn steps_without_an_upload_and_abort() {
    let mut tr = UploadTracker::new();
    assert_eq!(tr.chunk(0, &[1]), Err(UploadError::NotStarted));
    assert_eq!(tr.commit(0), Err(UploadError::NotStarted));
    assert_eq!(tr.abort(), Err(UploadError::NotStarted));
    let t = table(0.0);
    begin(&mut tr, &t);
    assert_eq!(tr.abort(), Ok(1));
    assert_eq!(tr.progress(), None);
}

#[test]
fn a_new_begin_replaces_an_unfinished_upload() {
    let (a, b) = (table(0.0), table(1.0));
    let mut tr = UploadTracker::new();
    begin(&mut tr, &a);
    tr.chunk(0, &a[..512]).unwrap();
    begin(&mut tr, &b);
    assert_eq!(tr.progress().unwrap().received, 0);
    send_all(&mut tr, &b);
    assert!(tr.commit(protocol::crc32::checksum(&b)).is_ok());
}

#[test]
fn verify_stored_catches_a_bad_flash_copy() {
    let t = table(0.0);
    let mut tr = UploadTracker::new();
    begin(&mut tr, &t);
    send_all(&mut tr, &t);
    let done = tr.commit(protocol::crc32::checksum(&t)).unwrap();
    let mut flash = t.clone();
    flash[1000] ^= 0x10; // a bit that did not program
    assert!(matches!(
        verify_stored(&done, &flash),
        Err(UploadError::Table(TableError::Crc { .. }))
    ));
    // A valid table of another shape in the slot is not the announced one.
    let other = Finished {
        header: GaitHeader {
            slice_count: 29,
            ..done.header
        },
        ..done
    };
    assert_eq!(verify_stored(&other, &t), Err(UploadError::HeaderMismatch));
}

/// A model of the firmware's rule "a slot is replaced only when the whole table has arrived and
/// verified": stage the accepted chunks, swap only after `commit` and `verify_stored` succeed.
#[test]
fn a_slot_keeps_its_old_table_through_every_refused_upload() {
    let old = table(0.0);
    let new = table(2.0);
    let crc = protocol::crc32::checksum(&new);
    let h = GaitTable::parse(&new).unwrap().header();
    type Step<'a> = &'a dyn Fn(&mut UploadTracker, &mut Vec<u8>) -> Result<Finished, UploadError>;
    let write = |tr: &mut UploadTracker, stage: &mut Vec<u8>, off: usize, data: &[u8]| {
        tr.chunk(off as u32, data)?;
        stage[off..off + data.len()].copy_from_slice(data);
        Ok::<_, UploadError>(())
    };
    let truncated: Step = &|tr, st| {
        write(tr, st, 0, &new[..512])?;
        tr.commit(crc)
    };
    let reordered: Step = &|tr, st| {
        write(tr, st, 512, &new[512..1024])?;
        tr.commit(crc)
    };
    let duplicated: Step = &|tr, st| {
        write(tr, st, 0, &new[..512])?;
        write(tr, st, 0, &new[..512])?;
        tr.commit(crc)
    };
    let oversized: Step = &|tr, st| {
        write(tr, st, 0, &new[..513])?;
        tr.commit(crc)
    };
    let wrong_crc: Step = &|tr, st| {
        for (i, c) in new.chunks(MAX_CHUNK_LEN).enumerate() {
            write(tr, st, i * MAX_CHUNK_LEN, c)?;
        }
        tr.commit(crc ^ 0xFFFF)
    };
    type Expect = fn(&UploadError) -> bool;
    let cases: [(Step, Expect); 5] = [
        (truncated, |e| matches!(e, UploadError::Truncated { .. })),
        (reordered, |e| matches!(e, UploadError::OutOfOrder { .. })),
        (duplicated, |e| matches!(e, UploadError::Duplicate { .. })),
        (oversized, |e| matches!(e, UploadError::ChunkTooLong { .. })),
        (wrong_crc, |e| {
            matches!(e, UploadError::ChecksumMismatch { .. })
        }),
    ];
    for (step, is_expected) in cases {
        let mut slot = old.clone();
        let mut stage = vec![0xFF; new.len()];
        let mut tr = UploadTracker::new();
        tr.begin(0, &h, new.len() as u32, &LIMITS).unwrap();
        let result = step(&mut tr, &mut stage)
            .and_then(|done| verify_stored(&done, &stage).map(|t| t.as_bytes().to_vec()));
        match result {
            Ok(bytes) => slot = bytes,
            Err(e) => assert!(is_expected(&e), "unexpected {e:?}"),
        }
        assert_eq!(slot, old, "the old table must survive");
        assert!(GaitTable::parse(&slot).is_ok());
    }
}

proptest::proptest! {
    /// Chunks delivered shuffled and repeated: the tracker lets through exactly the in-order ones, so a
    /// store that writes only accepted chunks and a host that then resumes at `received` always end
    /// with the exact table.
    #[test]
    fn shuffled_and_repeated_chunks_never_corrupt_the_staged_table(
        order in proptest::collection::vec(0usize..7, 0..30),
    ) {
        let t = table(0.5);
        let chunks: Vec<&[u8]> = t.chunks(MAX_CHUNK_LEN).collect();
        let mut tr = UploadTracker::new();
        begin(&mut tr, &t);
        let mut stage = vec![0xFFu8; t.len()];
        let mut deliver = |tr: &mut UploadTracker, i: usize| {
            let off = i * MAX_CHUNK_LEN;
            match tr.chunk(off as u32, chunks[i]) {
                Ok(_) => stage[off..off + chunks[i].len()].copy_from_slice(chunks[i]),
                Err(UploadError::Duplicate { .. } | UploadError::OutOfOrder { .. }) => {}
                Err(e) => panic!("chunk {i}: {e}"),
            }
        };
        for i in order {
            deliver(&mut tr, i);
        }
        let resume = tr.progress().unwrap().received as usize / MAX_CHUNK_LEN;
        for i in resume..chunks.len() {
            deliver(&mut tr, i);
        }
        let done = tr.commit(protocol::crc32::checksum(&t)).unwrap();
        proptest::prop_assert_eq!(verify_stored(&done, &stage).unwrap().as_bytes(), &t[..]);
    }
}

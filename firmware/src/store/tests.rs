//! Gait store against the NOR double: power loss at every tick of an upload, bad chunk sequences,
//! A/B alternation, delete.

use super::nor_double::NorDouble;
use super::record::CRC32;
use super::*;

/// 4 slots x 2 banks x 4 sectors.
const SECTORS: usize = 32;

/// A table of `len` bytes that differs per `seed` in every byte, so a mix of two tables is detectable.
fn table(len: usize, seed: u8) -> Vec<u8> {
    (0..len)
        .map(|i| (i as u8).wrapping_mul(31).wrapping_add(seed) ^ (i >> 8) as u8)
        .collect()
}

fn upload<F: NorFlash + FlashWindow>(
    store: &mut GaitStore<F>,
    slot: u8,
    data: &[u8],
    chunk: usize,
) -> Result<SlotInfo, StoreError> {
    store.begin(slot, data.len() as u32)?;
    for (i, c) in data.chunks(chunk).enumerate() {
        store.write((i * chunk) as u32, c)?;
    }
    store.commit(CRC32.checksum(data))
}

/// `flash` with slot 0 uploaded twice in `chunk`-byte chunks: an older table (seed 1) in one bank,
/// then the current one (seed 2), `len` bytes each, in the other. Returns the flash and both.
fn older_and_current<F: NorFlash + FlashWindow>(
    flash: F,
    len: usize,
    chunk: usize,
) -> (F, Vec<u8>, Vec<u8>) {
    let mut store = GaitStore::mount(flash, 4);
    let (older, cur) = (table(len, 1), table(len, 2));
    upload(&mut store, 0, &older, chunk).unwrap();
    upload(&mut store, 0, &cur, chunk).unwrap();
    (store.into_flash(), older, cur)
}

#[test]
fn upload_reads_back_in_place_and_survives_a_remount() {
    let mut store = GaitStore::mount(NorDouble::<4>::new(SECTORS), 4);
    assert_eq!(store.max_table_len(), 4 * 4096 - 256);
    let t = table(5000, 1);
    // 7-byte chunks exercise the tail that carries bytes over the 4-byte write unit.
    let info = upload(&mut store, 2, &t, 7).unwrap();
    assert_eq!((info.slot, info.len, info.seq), (2, 5000, 1));
    assert_eq!(store.table(2), Some(&t[..]));
    // In place: the slice points into the flash window, past the 256-byte header of bank A of slot 2.
    let window = store.flash.window().as_ptr() as usize;
    assert_eq!(
        store.table(2).unwrap().as_ptr() as usize - window,
        2 * 2 * 4 * 4096 + 256
    );
    assert_eq!(store.table(0), None);
    let store = GaitStore::mount(store.into_flash(), 4);
    assert_eq!(store.table(2), Some(&t[..]));
    assert_eq!(store.info(2).unwrap().crc, CRC32.checksum(&t));
}

#[test]
fn successive_uploads_alternate_banks_and_the_newest_wins() {
    let mut store = GaitStore::mount(NorDouble::<4>::new(SECTORS), 4);
    for seed in 1..=5u8 {
        let t = table(3000 + seed as usize * 100, seed);
        assert_eq!(upload(&mut store, 1, &t, 64).unwrap().seq, seed as u32);
        let offset =
            store.table(1).unwrap().as_ptr() as usize - store.flash.window().as_ptr() as usize;
        // Bank A of slot 1 starts at 8 sectors, bank B at 12: odd uploads land in A, even in B.
        let bank_start = if seed % 2 == 1 { 8 * 4096 } else { 12 * 4096 };
        assert_eq!(offset, bank_start + 256, "upload {seed}");
        store = GaitStore::mount(store.into_flash(), 4);
        assert_eq!(store.table(1), Some(&t[..]));
    }
}

/// Uploads `new` over a slot holding `old` (after `history` earlier uploads, so the spare bank may hold
/// an older valid table) with the power failing after `k` ticks, for every `k` until the upload
/// completes: after the power returns the slot holds exactly `old` or exactly `new`, and `new` as soon
/// as the commit record was completely written.
fn power_loss_sweep(history: u8) {
    let old = table(5000, 10);
    let new = table(6100, 20);
    let mut base = GaitStore::mount(NorDouble::<4>::new(SECTORS), 4);
    for h in 0..history {
        upload(&mut base, 3, &table(4000, 30 + h), 256).unwrap();
    }
    upload(&mut base, 3, &old, 256).unwrap();
    let flash = base.into_flash();

    // Ticks of an undisturbed upload: erase + table bytes + record.
    let mut clean = GaitStore::mount(flash.clone(), 4);
    let before = clean.flash.ticks;
    upload(&mut clean, 3, &new, 256).unwrap();
    let total = clean.flash.ticks - before;
    assert_eq!(
        total,
        2 + 6100 + 32,
        "two sectors erased, table and padded record programmed"
    );
    let commit = 2 + 6100 + 24;

    let (mut saw_old, mut saw_new) = (0, 0);
    for k in 0..=total {
        let mut f = flash.clone();
        f.lose_power_after(k);
        let mut store = GaitStore::mount(f, 4);
        let result = upload(&mut store, 3, &new, 256);
        let mut f = store.into_flash();
        assert_eq!(result.is_ok(), k == total, "power lost after {k} ticks");
        f.power_cycle();
        let store = GaitStore::mount(f, 4);
        let holds = match store.table(3) {
            Some(t) if t == &old[..] => "old",
            Some(t) if t == &new[..] => "new",
            Some(_) => "a mix",
            None => "nothing",
        };
        // The commit is the last of the 24 record bytes; the 8 padding bytes after it change nothing.
        let want = if k < commit { "old" } else { "new" };
        assert_eq!(holds, want, "power lost after {k} of {total} ticks");
        match holds {
            "old" => saw_old += 1,
            _ => saw_new += 1,
        }
        // Other slots are never touched.
        assert_eq!(store.table(0), None);
    }
    assert_eq!((saw_old, saw_new), (commit, total - commit + 1));
}

#[test]
fn power_loss_at_every_tick_of_an_upload_into_an_empty_spare_bank() {
    power_loss_sweep(0);
}

#[test]
fn power_loss_at_every_tick_of_an_upload_over_an_older_valid_bank() {
    power_loss_sweep(1);
}

#[test]
fn power_loss_at_every_tick_of_a_delete_leaves_the_table_or_nothing() {
    let (flash, _, cur) = older_and_current(NorDouble::<4>::new(SECTORS), 3000, 500);
    for k in 0..=2 {
        let mut f = flash.clone();
        f.lose_power_after(k);
        let mut store = GaitStore::mount(f, 4);
        assert_eq!(store.delete(0).is_ok(), k == 2);
        let mut f = store.into_flash();
        f.power_cycle();
        let store = GaitStore::mount(f, 4);
        let holds = store.table(0).map(|t| t == &cur[..]);
        // Tick 0 is the erase of the older bank; once the current bank's erase has begun (tick 1)
        // its record is gone: the slot is empty, never holding the older table again.
        let want = if k < 1 { Some(true) } else { None };
        assert_eq!(holds, want, "power lost after {k} ticks");
    }
}

#[test]
fn bad_chunk_sequences_are_refused_and_the_old_table_stays() {
    let old = table(2000, 1);
    let new = table(2000, 2);
    let fresh = || {
        let mut s = GaitStore::mount(NorDouble::<4>::new(SECTORS), 4);
        upload(&mut s, 0, &old, 100).unwrap();
        s
    };
    let check_old = |s: GaitStore<NorDouble<4>>| {
        assert_eq!(s.table(0), Some(&old[..]));
        let s = GaitStore::mount(s.into_flash(), 4);
        assert_eq!(s.table(0), Some(&old[..]));
    };

    // Each sequence on a store holding `old`, and the refusals its last steps end with (the
    // steps before them accepted).
    let good = CRC32.checksum(&new);
    let cases: [(&str, &[Op], &[StoreError]); 7] = [
        (
            "truncated: commit before the last chunk",
            &[Op::Begin(0, 2000), Op::Write(0..1900), Op::Commit(good)],
            &[StoreError::Incomplete {
                received: 1900,
                total: 2000,
            }],
        ),
        (
            "reordered: the second chunk first",
            &[Op::Begin(0, 2000), Op::Write(1000..2000)],
            &[StoreError::OutOfOrder {
                expected: 0,
                got: 1000,
            }],
        ),
        (
            "duplicated: the first chunk twice",
            &[Op::Begin(0, 2000), Op::Write(0..1000), Op::Write(0..1000)],
            &[StoreError::OutOfOrder {
                expected: 1000,
                got: 0,
            }],
        ),
        (
            "oversized: a chunk past the announced size",
            &[Op::Begin(0, 2000), Op::Write(0..1500), Op::Zeros(1500, 501)],
            &[StoreError::Overflow {
                offset: 1500,
                len: 501,
                total: 2000,
            }],
        ),
        (
            "oversized: a table larger than a bank",
            &[Op::Begin(0, 4 * 4096 - 255)],
            &[StoreError::BadSize {
                len: 4 * 4096 - 255,
                max: 4 * 4096 - 256,
            }],
        ),
        (
            "wrong checksum: every byte arrived, the announced CRC is not theirs; the failed \
             commit ended the upload",
            &[
                Op::Begin(0, 2000),
                Op::Write(0..2000),
                Op::Commit(good ^ 1),
                Op::Commit(good),
            ],
            &[
                StoreError::ChecksumMismatch {
                    expected: good ^ 1,
                    actual: good,
                },
                StoreError::NoUpload,
            ],
        ),
        (
            "no such slot",
            &[Op::Begin(4, 10)],
            &[StoreError::NoSuchSlot { slot: 4, slots: 4 }],
        ),
    ];
    for (what, ops, refusals) in cases {
        let mut s = fresh();
        let results: Vec<_> = ops.iter().map(|op| op.apply(&mut s, &new)).collect();
        let (accepted, refused) = results.split_at(ops.len() - refusals.len());
        assert!(accepted.iter().all(Result::is_ok), "{what}: {results:?}");
        let want: Vec<_> = refusals.iter().map(|&e| Err(e)).collect();
        assert_eq!(refused, &want[..], "{what}");
        check_old(s);
    }
}

/// One step of an upload of `new`.
#[derive(Debug)]
enum Op {
    /// `begin(slot, total)`.
    Begin(u8, u32),
    /// The bytes of `new` in the range, written at its start.
    Write(core::ops::Range<usize>),
    /// `len` zero bytes at `offset`.
    Zeros(u32, usize),
    /// `commit(crc)`.
    Commit(u32),
}

impl Op {
    fn apply(&self, s: &mut GaitStore<NorDouble<4>>, new: &[u8]) -> Result<(), StoreError> {
        match self {
            Op::Begin(slot, total) => s.begin(*slot, *total),
            Op::Write(r) => s.write(r.start as u32, &new[r.clone()]),
            Op::Zeros(offset, len) => s.write(*offset, &std::vec![0; *len]),
            Op::Commit(crc) => s.commit(*crc).map(drop),
        }
    }
}

#[test]
fn a_byte_rotting_in_flash_invalidates_only_that_bank() {
    let (mut f, older, _) = older_and_current(NorDouble::<1>::new(SECTORS), 1000, 1000);
    // Clear one bit of the current table (bank B of slot 0): the CRC check at mount rejects the bank
    // and the older table comes back rather than a corrupt one.
    let at = 4 * 4096 + 256 + 10;
    let byte = f.window()[at];
    let bit = byte.trailing_zeros().min(7);
    let flipped = byte & !(1 << bit);
    embedded_storage::nor_flash::NorFlash::write(&mut f, at as u32, &[flipped]).unwrap();
    let store = GaitStore::mount(f, 4);
    assert_eq!(store.table(0), Some(&older[..]));
}

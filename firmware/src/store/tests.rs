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
    let mut store = GaitStore::mount(NorDouble::<4>::new(SECTORS), 4);
    let older = table(3000, 1);
    let cur = table(3000, 2);
    upload(&mut store, 0, &older, 500).unwrap();
    upload(&mut store, 0, &cur, 500).unwrap();
    let flash = store.into_flash();
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

    // Truncated: commit before the last chunk.
    let mut s = fresh();
    s.begin(0, 2000).unwrap();
    s.write(0, &new[..1900]).unwrap();
    assert_eq!(
        s.commit(CRC32.checksum(&new)),
        Err(StoreError::Incomplete {
            received: 1900,
            total: 2000
        })
    );
    check_old(s);

    // Reordered: the second chunk first.
    let mut s = fresh();
    s.begin(0, 2000).unwrap();
    assert_eq!(
        s.write(1000, &new[1000..]),
        Err(StoreError::OutOfOrder {
            expected: 0,
            got: 1000
        })
    );
    check_old(s);

    // Duplicated: the first chunk twice.
    let mut s = fresh();
    s.begin(0, 2000).unwrap();
    s.write(0, &new[..1000]).unwrap();
    assert_eq!(
        s.write(0, &new[..1000]),
        Err(StoreError::OutOfOrder {
            expected: 1000,
            got: 0
        })
    );
    check_old(s);

    // Oversized: a chunk past the announced size, and a table larger than a bank.
    let mut s = fresh();
    s.begin(0, 2000).unwrap();
    s.write(0, &new[..1500]).unwrap();
    assert_eq!(
        s.write(1500, &[0; 501]),
        Err(StoreError::Overflow {
            offset: 1500,
            len: 501,
            total: 2000
        })
    );
    assert_eq!(
        s.begin(0, 4 * 4096 - 255),
        Err(StoreError::BadSize {
            len: 4 * 4096 - 255,
            max: 4 * 4096 - 256
        })
    );
    check_old(s);

    // Wrong checksum: every byte arrived, the announced CRC is not theirs.
    let mut s = fresh();
    s.begin(0, 2000).unwrap();
    s.write(0, &new).unwrap();
    let good = CRC32.checksum(&new);
    assert_eq!(
        s.commit(good ^ 1),
        Err(StoreError::ChecksumMismatch {
            expected: good ^ 1,
            actual: good
        })
    );
    // The failed commit ended the upload.
    assert_eq!(s.commit(good), Err(StoreError::NoUpload));
    check_old(s);

    // No such slot.
    let mut s = fresh();
    assert_eq!(
        s.begin(4, 10),
        Err(StoreError::NoSuchSlot { slot: 4, slots: 4 })
    );
    check_old(s);
}

#[test]
fn a_byte_rotting_in_flash_invalidates_only_that_bank() {
    let mut store = GaitStore::mount(NorDouble::<1>::new(SECTORS), 4);
    let older = table(1000, 1);
    let cur = table(1000, 2);
    upload(&mut store, 0, &older, 1000).unwrap();
    upload(&mut store, 0, &cur, 1000).unwrap();
    let mut f = store.into_flash();
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

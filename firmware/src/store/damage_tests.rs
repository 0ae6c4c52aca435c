//! What mount reports about damaged data: a flipped byte in the live bank makes the slot fall back
//! and says which copy was lost and why; random bytes over the whole store read as damaged, an
//! erased store as empty; a committed upload clears the mark, also across a remount.

use super::nor_double::NorDouble;
use super::record::CRC32;
use super::*;

/// 4 slots x 2 banks x 4 sectors (bank size 16 KB).
const SECTORS: usize = 32;
const BANK: usize = 4 * 4096;

fn table(len: usize, seed: u8) -> Vec<u8> {
    (0..len)
        .map(|i| (i as u8).wrapping_mul(37).wrapping_add(seed))
        .collect()
}

fn upload(store: &mut GaitStore<NorDouble<4>>, slot: u8, data: &[u8]) -> SlotInfo {
    store.begin(slot, data.len() as u32).unwrap();
    store.write(0, data).unwrap();
    store.commit(CRC32.checksum(data)).unwrap()
}

/// The flash with `edit` applied to its bytes (a new double programmed with them, as the virtual
/// robot loads its image file).
fn edited(flash: NorDouble<4>, edit: impl FnOnce(&mut [u8])) -> NorDouble<4> {
    let mut bytes = flash.window().to_vec();
    edit(&mut bytes);
    let mut f = NorDouble::<4>::new(SECTORS);
    f.write(0, &bytes).unwrap();
    f
}

/// Slot 0 after two uploads: `older` (seq 1) in bank A, `newer` (seq 2, live) in bank B.
fn two_uploads() -> (NorDouble<4>, Vec<u8>, Vec<u8>) {
    let mut store = GaitStore::mount(NorDouble::<4>::new(SECTORS), 4);
    let older = table(1000, 1);
    let newer = table(1200, 2);
    upload(&mut store, 0, &older);
    upload(&mut store, 0, &newer);
    (store.into_flash(), older, newer)
}

#[test]
fn a_flipped_table_byte_in_the_live_bank_is_reported_as_a_fallback_with_its_reason() {
    let (flash, older, newer) = two_uploads();
    let at = BANK + 256 + 10;
    let flash = edited(flash, |m| m[at] ^= 0x01);
    let store = GaitStore::mount(flash, 4);
    assert_eq!(store.table(0), Some(&older[..]));
    assert_eq!(store.info(0).unwrap().seq, 1);
    let mut damaged = newer.clone();
    damaged[10] ^= 0x01;
    assert_eq!(
        store.lost(0),
        Some(LostCopy {
            bank: 1,
            seq: Some(2),
            len: Some(1200),
            crc: Some(CRC32.checksum(&newer)),
            reason: LossReason::TableChecksum {
                actual: CRC32.checksum(&damaged)
            },
        })
    );
    // What is left of the lost table can still be read (its first bytes are intact).
    assert_eq!(store.lost_bytes(0).unwrap()[..10], newer[..10]);
    assert!(store.damaged());
    for slot in 1..4 {
        assert_eq!(store.lost(slot), None, "slot {slot}");
    }
}

#[test]
fn a_flipped_record_byte_in_the_live_bank_is_reported_as_a_damaged_record() {
    let (flash, older, _) = two_uploads();
    // Byte 9 of the record is in its sequence number: the record's own CRC fails.
    let flash = edited(flash, |m| m[BANK + 9] ^= 0x40);
    let store = GaitStore::mount(flash, 4);
    assert_eq!(store.table(0), Some(&older[..]));
    let lost = store.lost(0).unwrap();
    assert_eq!((lost.bank, lost.seq), (1, None));
    assert_eq!(lost.reason, LossReason::RecordDamaged);
}

#[test]
fn a_rotten_older_copy_is_not_a_fallback() {
    let (flash, _, newer) = two_uploads();
    // Bank A holds the older table (seq 1): damage there loses nothing current.
    let flash = edited(flash, |m| m[256 + 3] ^= 0x80);
    let store = GaitStore::mount(flash, 4);
    assert_eq!(store.table(0), Some(&newer[..]));
    assert_eq!(store.lost(0), None);
    assert!(!store.damaged());
}

#[test]
fn random_bytes_over_the_whole_store_read_as_damaged_not_empty() {
    // xorshift32, fixed seed: the same bytes every run.
    let mut x = 0x1234_5678u32;
    let flash = edited(NorDouble::<4>::new(SECTORS), |m| {
        for b in m.iter_mut() {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            *b = x as u8;
        }
    });
    let store = GaitStore::mount(flash, 4);
    assert!(store.damaged());
    for slot in 0..4 {
        assert_eq!(store.table(slot), None, "slot {slot}");
        let lost = store.lost(slot).unwrap();
        assert_eq!(lost.reason, LossReason::RecordDamaged, "slot {slot}");
    }
}

#[test]
fn an_erased_store_is_empty_not_damaged() {
    let store = GaitStore::mount(NorDouble::<4>::new(SECTORS), 4);
    assert!(!store.damaged());
    for slot in 0..4 {
        assert_eq!((store.table(slot), store.lost(slot)), (None, None));
    }
    // A half-written upload (table bytes, no record) is not damage either: it never committed.
    let mut store = store;
    store.begin(1, 3000).unwrap();
    store.write(0, &table(2000, 5)).unwrap();
    let store = GaitStore::mount(store.into_flash(), 4);
    assert!(!store.damaged());
}

#[test]
fn an_upload_after_a_fallback_clears_the_mark_also_after_a_remount() {
    let (flash, older, _) = two_uploads();
    let flash = edited(flash, |m| m[BANK + 256 + 10] ^= 0x01);
    let mut store = GaitStore::mount(flash, 4);
    assert!(store.lost(0).is_some());
    let fresh = table(900, 3);
    // The fallback copy stays usable until the new upload commits.
    store.begin(0, 900).unwrap();
    assert_eq!(store.table(0), Some(&older[..]));
    assert!(store.lost(0).is_some());
    store.write(0, &fresh).unwrap();
    let info = store.commit(CRC32.checksum(&fresh)).unwrap();
    assert_eq!(info.seq, 2);
    assert_eq!(store.lost(0), None);
    let store = GaitStore::mount(store.into_flash(), 4);
    assert_eq!(store.table(0), Some(&fresh[..]));
    assert_eq!(store.lost(0), None);
    assert!(!store.damaged());
}

#[test]
fn an_upload_into_a_fully_damaged_slot_clears_both_banks_marks() {
    let (flash, _, _) = two_uploads();
    // Both records of slot 0 damaged: no valid copy at all.
    let flash = edited(flash, |m| {
        m[9] ^= 0x40;
        m[BANK + 9] ^= 0x40;
    });
    let mut store = GaitStore::mount(flash, 4);
    assert_eq!(store.table(0), None);
    assert_eq!(store.lost(0).unwrap().reason, LossReason::RecordDamaged);
    let fresh = table(700, 4);
    upload(&mut store, 0, &fresh);
    let store = GaitStore::mount(store.into_flash(), 4);
    assert_eq!(store.table(0), Some(&fresh[..]));
    assert_eq!(store.lost(0), None);
}

#[test]
fn deleting_a_slot_clears_its_mark() {
    let (flash, _, _) = two_uploads();
    let flash = edited(flash, |m| m[BANK + 256] ^= 0x01);
    let mut store = GaitStore::mount(flash, 4);
    store.delete(0).unwrap();
    assert_eq!(store.lost(0), None);
    let store = GaitStore::mount(store.into_flash(), 4);
    assert_eq!((store.table(0), store.lost(0)), (None, None));
}

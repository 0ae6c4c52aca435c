//! Gait-table validation: any bytes give a table or an error; a table that validates answers every
//! accessor in bounds and keeps its invariants. With the first byte odd the input gets a plausible
//! header (magic, version, length from its counts, CRC) so validation reaches the joint records and
//! slices instead of stopping at the magic or the CRC.
#![no_main]

use libfuzzer_sys::fuzz_target;
use protocol::gait::{self, GaitTable, HEADER_LEN, MAGIC, STANCE_MASK};

fn plausible(mut t: Vec<u8>) -> Vec<u8> {
    if t.len() < HEADER_LEN + 4 {
        t.resize(HEADER_LEN + 4, 0);
    }
    let joints = usize::from(t[6] % 40);
    let slices = usize::from(u16::from_le_bytes([t[8], t[9]]) % 64);
    let len = gait::table_len(joints, slices);
    t.resize(len.max(HEADER_LEN + 4), 0);
    t[..4].copy_from_slice(&MAGIC);
    t[4..6].copy_from_slice(&gait::FORMAT_VERSION.to_le_bytes());
    t[6] = joints as u8;
    t[8..10].copy_from_slice(&(slices as u16).to_le_bytes());
    t[16..20].copy_from_slice(&(len as u32).to_le_bytes());
    let n = len.max(HEADER_LEN + 4);
    let crc = protocol::crc32::checksum(&t[..n - 4]);
    t[n - 4..n].copy_from_slice(&crc.to_le_bytes());
    t
}

fuzz_target!(|data: &[u8]| {
    let Some((&mode, rest)) = data.split_first() else { return };
    let bytes = if mode & 1 == 1 { plausible(rest.to_vec()) } else { rest.to_vec() };
    let Ok(table) = GaitTable::parse(&bytes) else { return };
    let h = table.header();
    assert_eq!(table.as_bytes().len() as u32, h.table_len());
    assert_eq!(protocol::crc32::checksum(&table.as_bytes()[..table.as_bytes().len() - 4]), table.crc());
    for s in 0..=table.slice_count() {
        if let Some(stance) = table.stance(s) {
            assert_eq!(stance & !STANCE_MASK, 0);
        }
        for j in 0..=table.joint_count() {
            match (table.joint(j), table.angle(s, j), table.torque(s, j)) {
                (Some(map), Some(angle), Some(_)) => assert!(map.min <= angle && angle <= map.max),
                (_, None, None) => assert!(s == table.slice_count() || j == table.joint_count()),
                other => panic!("inconsistent accessors at slice {s} joint {j}: {other:?}"),
            }
        }
    }
});

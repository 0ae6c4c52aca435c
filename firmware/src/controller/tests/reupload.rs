//! A new table uploaded into the selected slot is the one played: its slices, period and samples,
//! although the CRC-32 over each whole table (its own CRC included) is the same constant.

use super::*;

/// The CRC-32 residue: the CRC-32 of any message followed by its own CRC-32 (little-endian) is
/// this constant, the complement of the CRC-32/ISO-HDLC catalogue entry's `residue` 0xDEBB20E3
/// (which is taken before the final complement).
const CRC32_RESIDUE: u32 = 0x2144_DF1C;

#[test]
fn a_table_uploaded_into_the_selected_slot_plays_its_own_slices_and_period() {
    // Slot 0 holds the synthetic gait at 100 slices over 1 s; it is selected and played.
    let mut r = Rig::idle();
    r.play(Some(1));
    r.until(2000, State::Standing);
    // A new table into the same slot: 20 slices over 2 s. Both tables' whole-table CRC-32s are
    // the residue, so that checksum cannot tell them apart.
    let short = SyntheticGait::new(20, 2.0);
    let table = short.build();
    assert_eq!(CRC32.checksum(&r.gait.build()), CRC32_RESIDUE);
    assert_eq!(CRC32.checksum(&table), CRC32_RESIDUE);
    upload(&mut r.c, 0, &table);
    r.play(Some(1));
    r.until(2000, State::Walking);
    // Every cycle's goals are the new table's, interpolated at its own clock (testkit formula),
    // from its 20 slices.
    let cycles = r.walk_checking_goals(&short);
    // One step of 2 s at 100 Hz (the old table's would have been 1 s).
    assert_eq!(cycles, 200);
    assert_eq!(r.c.state(), State::Standing);
}

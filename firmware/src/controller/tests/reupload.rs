//! A new table uploaded into the selected slot is the one played: its slices, period and samples,
//! although the CRC-32 over each whole table (its own CRC included) is the same constant.

use super::switch::upload;
use super::*;

/// The CRC-32 residue: the CRC-32 of any message followed by its own CRC-32 (little-endian) is
/// this constant, the complement of the CRC-32/ISO-HDLC catalogue entry's `residue` 0xDEBB20E3
/// (which is taken before the final complement).
const CRC32_RESIDUE: u32 = 0x2144_DF1C;

#[test]
fn a_table_uploaded_into_the_selected_slot_plays_its_own_slices_and_period() {
    // Slot 0 holds the synthetic gait at 100 slices over 1 s; it is selected and played.
    let mut r = Rig::new();
    r.cycle();
    r.play(Some(1));
    r.cycles_until(2000, |r| r.c.state() == State::Standing);
    // A new table into the same slot: 20 slices over 2 s. Both tables' whole-table CRC-32s are
    // the residue, so that checksum cannot tell them apart.
    let short = SyntheticGait::new(20, 2.0);
    let table = short.build();
    assert_eq!(CRC32.checksum(&r.gait.build()), CRC32_RESIDUE);
    assert_eq!(CRC32.checksum(&table), CRC32_RESIDUE);
    upload(&mut r.c, 0, &table);
    r.play(Some(1));
    r.cycles_until(2000, |r| r.c.state() == State::Walking);
    // Every cycle's goals are the new table's, interpolated at its own clock (testkit formula).
    let mut cycles = 0;
    while r.c.state() == State::Walking {
        let t_before = r.c.play_clock().unwrap().phase_us();
        r.cycle();
        cycles += 1;
        if r.c.state() != State::Walking {
            break;
        }
        let (_, slice) = r.c.playback().unwrap();
        assert!(
            slice < 20,
            "cycle {cycles}: slice {slice} of a 20-slice table"
        );
        let t = (t_before + 10_000) % 2_000_000;
        let pos = t as f64 / 2e6 * 20.0;
        for j in 0..JOINTS {
            let want = short.goal(pos, j, STIFFNESS);
            assert!(
                (r.servos.pos[j] as f64 - want).abs() <= 1.0,
                "cycle {cycles} joint {j}: {} vs {want:.2}",
                r.servos.pos[j]
            );
        }
    }
    // One step of 2 s at 100 Hz (the old table's would have been 1 s).
    assert_eq!(cycles, 200);
    assert_eq!(r.c.state(), State::Standing);
}

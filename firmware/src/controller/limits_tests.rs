//! The controller's run-time settings against what the hardware can do (`protocol::limits`):
//! bauds the MX servos do not support, rates whose cycles do not fit the wire, stiffness beyond a
//! servo. Before these checks the controller took any baud from 9600 to 4.5 M, 1000 Hz at
//! 57 600 bit/s (about 9 Hz fit), and any stiffness (issue #19, item 5).

use super::*;
use crate::store::nor_double::NorDouble;
use crate::store::record::CRC32;
use crate::testkit::{JOINTS, SyntheticGait};

/// A controller at 1 Mbit/s and 100 Hz whose slot 0 holds the 22-joint synthetic gait (so that
/// it has a joint map), as after a power cycle.
fn controller() -> Controller<NorDouble<4>> {
    let table = SyntheticGait::new(100, 1.0).build();
    let mut c = Controller::new(NorDouble::new(64), 4, Config::default());
    c.upload_begin(0, table.len() as u32).unwrap();
    c.upload_chunk(0, &table).unwrap();
    c.upload_commit(CRC32.checksum(&table)).unwrap();
    let c = Controller::new(c.into_flash(), 4, Config::default());
    assert_eq!(c.joints().len(), JOINTS);
    c
}

#[test]
fn the_baud_list_is_the_servos_register_table() {
    let register: Vec<u32> = dynamixel::control_table::BAUD_RATES
        .iter()
        .map(|(_, b)| *b)
        .collect();
    assert_eq!(register, protocol::limits::MX_BAUDS);
}

#[test]
fn a_baud_the_servos_do_not_support_is_refused_and_nothing_changes() {
    let mut c = controller();
    assert_eq!(
        c.set_bus(12_345, 100),
        Err(CommandError::OutOfRange {
            what: Setting::Baud,
            value: 12_345
        })
    );
    assert_eq!((c.config().baud, c.config().cycle_hz), (1_000_000, 100));
}

#[test]
fn a_rate_beyond_the_wire_is_refused_at_the_hand_computed_limit() {
    // 22 servos: 622 bytes x 10 bits per cycle. 57 600 bit/s carries 9.26 cycles/s, below the
    // slowest rate the loop accepts; 1 Mbit/s carries 160.8.
    let mut c = controller();
    let refused = Err(CommandError::OutOfRange {
        what: Setting::CycleRate,
        value: 1000,
    });
    assert_eq!(c.set_bus(57_600, 1000), refused);
    assert!(c.set_bus(57_600, 50).is_err());
    assert!(c.set_bus(1_000_000, 161).is_err());
    assert_eq!(c.set_bus(1_000_000, 160), Ok(()));
    assert_eq!(c.set_bus(4_000_000, 643), Ok(()));
    assert!(c.set_bus(4_000_000, 644).is_err());
}

#[test]
fn a_stiffness_beyond_the_servo_is_refused_and_zero_still_switches_the_bias_off() {
    let mut c = controller();
    // What P gain 1 ..= 16383 gives (hand computed in protocol::limits): MX-28 7 ..= 235 708
    // mN m/rad, MX-64 17 ..= 565 699. 1 mN m/rad (accepted before) would make the bias ask
    // 500 rad of a 0.5 N m joint.
    for j in 0..c.joints().len() as u8 {
        let (least, most) = match c.joints()[usize::from(j)].model {
            dynamixel::ServoModel::Mx28 => (7, 235_708),
            dynamixel::ServoModel::Mx64 => (17, 565_699),
        };
        for bad in [
            1,
            least - 1,
            most + 1,
            protocol::limits::MAX_STIFFNESS_UNITS,
        ] {
            assert_eq!(
                c.set_stiffness(j, bad),
                Err(CommandError::OutOfRange {
                    what: Setting::Stiffness,
                    value: i64::from(bad)
                }),
                "joint {j}: {bad} mN m/rad"
            );
        }
        assert_eq!(c.set_stiffness(j, least), Ok(()));
        assert_eq!(c.set_stiffness(j, most), Ok(()));
        assert_eq!(c.set_stiffness(j, 0), Ok(()));
        assert_eq!(c.stiffness()[usize::from(j)], 0);
    }
}

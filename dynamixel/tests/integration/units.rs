//! Unit conversions against hand calculations from the e-manual's units (4096 ticks/rev,
//! 0.229 rev/min, 0.1 % load, 3.36 mA) and the datasheet stall figures.

use dynamixel::ServoModel;
use dynamixel::control_table::{GOAL_POSITION, baud_code, baud_from_code, field_by_name};
use dynamixel::units::*;

#[test]
fn tick_and_velocity_units() {
    // 0.088 deg per tick (e-manual).
    assert!((RAD_PER_TICK.to_degrees() - 0.0879).abs() < 1e-4);
    // 240 units x 0.229 rev/min = 54.96 rev/min = 5.755 rad/s.
    assert!((velocity_to_rad_s(240) - 5.7554).abs() < 1e-3);
}

#[test]
fn load_and_current_to_torque_estimates() {
    // MX-28: 400 = 40.0 % of 2.5 N m = 1.0 N m.
    assert!((load_to_torque_nm(ServoModel::Mx28, 400) - 1.0).abs() < 1e-6);
    assert_eq!(load_to_torque_mnm(ServoModel::Mx28, 400), 1000);
    // MX-64: 203 x 3.36 mA = 682 mA; x 6.0 N m / 4.1 A = 0.998 N m.
    assert!((load_to_torque_nm(ServoModel::Mx64, 203) - 0.998).abs() < 1e-3);
    assert_eq!(load_to_torque_mnm(ServoModel::Mx64, 203), 998);
    assert_eq!(torque_to_load(ServoModel::Mx28, -1.0), -400);
    assert_eq!(
        torque_to_load(ServoModel::Mx28, 10.0),
        1000,
        "MX-28 load saturates at 100 %"
    );
}

#[test]
fn stiffness_from_p_gain() {
    // (850/128)/885 x 2.5 N m per tick x 4096/(2 pi) ticks/rad = 12.23 N m/rad.
    assert!((stiffness_nm_per_rad(ServoModel::Mx28, 850) - 12.23).abs() < 0.01);
    assert!((stiffness_nm_per_rad(ServoModel::Mx64, 850) - 29.35).abs() < 0.01);
}

#[test]
fn p_gain_for_stiffness_inverts_the_stiffness_conversion() {
    // Hand: 1 P unit = (1/128)/885 x stall torque x 4096/(2 pi) = 0.014387 N m/rad (MX-28, 2.5 N m)
    // and 0.034529 N m/rad (MX-64, 6.0 N m). 8.4 / 0.014387 = 583.86 -> 584; 20 / 0.034529 =
    // 579.23 -> 579; 12.23 / 0.014387 = 850.08 -> 850 (the default gain).
    assert_eq!(p_gain_for_stiffness(ServoModel::Mx28, 8.4), 584);
    assert_eq!(p_gain_for_stiffness(ServoModel::Mx64, 20.0), 579);
    assert_eq!(p_gain_for_stiffness(ServoModel::Mx28, 12.23), 850);
    // No stiffness is no gain; a tiny one is the smallest gain, never the limp 0; a huge one the
    // register's top (e-manual range 0..16383).
    assert_eq!(p_gain_for_stiffness(ServoModel::Mx28, 0.0), 0);
    assert_eq!(p_gain_for_stiffness(ServoModel::Mx28, -1.0), 0);
    assert_eq!(p_gain_for_stiffness(ServoModel::Mx28, f32::NAN), 0);
    assert_eq!(p_gain_for_stiffness(ServoModel::Mx28, 0.001), 1);
    assert_eq!(p_gain_for_stiffness(ServoModel::Mx28, 1000.0), P_GAIN_MAX);
    assert_eq!(P_GAIN_MAX, 16_383);
    // Round trip: every register value comes back from its own stiffness.
    for model in [ServoModel::Mx28, ServoModel::Mx64] {
        for p in 1..=P_GAIN_MAX {
            assert_eq!(
                p_gain_for_stiffness(model, stiffness_nm_per_rad(model, p)),
                p
            );
        }
    }
}

#[test]
fn control_table_lookups() {
    assert_eq!(field_by_name("goal_position"), Some(GOAL_POSITION));
    assert_eq!(
        field_by_name("Present Load/Current").map(|f| (f.addr, f.size)),
        Some((126, 2))
    );
    assert_eq!(field_by_name("no such"), None);
    assert_eq!(
        (baud_code(1_000_000), baud_from_code(1), baud_code(12345)),
        (Some(3), Some(57_600), None)
    );
    assert_eq!(
        (ServoModel::Mx28.number(), ServoModel::Mx64.number()),
        (30, 311)
    );
}

#[test]
fn the_fields_are_in_address_order_without_overlaps() {
    // The virtual servo's write finds the fields it touches by bisection on this order.
    use dynamixel::control_table::FIELDS;
    for w in FIELDS.windows(2) {
        assert!(
            w[0].addr + w[0].size as u16 <= w[1].addr,
            "{} ({}+{}) runs into {} ({})",
            w[0].name,
            w[0].addr,
            w[0].size,
            w[1].name,
            w[1].addr
        );
    }
}

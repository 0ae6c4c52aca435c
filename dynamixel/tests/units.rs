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

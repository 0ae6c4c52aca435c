//! Unit conversions against hand calculations from the e-manual's units (4096 ticks/rev,
//! 0.229 rev/min, 0.1 % load, 3.36 mA) and the datasheet stall figures.

use dynamixel::control_table::{GOAL_POSITION, Model, baud_code, baud_from_code, field_by_name};
use dynamixel::units::*;

#[test]
fn ticks_and_radians_with_offset_and_direction() {
    let j = JointCalibration {
        zero_ticks: 2048,
        reversed: false,
    };
    // A quarter turn is 1024 ticks.
    assert!((j.ticks_to_rad(3072) - core::f32::consts::FRAC_PI_2).abs() < 1e-6);
    assert_eq!(j.rad_to_ticks(core::f32::consts::FRAC_PI_2), 3072);
    let r = JointCalibration {
        zero_ticks: 1000,
        reversed: true,
    };
    assert!((r.ticks_to_rad(0) - 1000.0 * core::f32::consts::TAU / 4096.0).abs() < 1e-5);
    assert_eq!(r.rad_to_ticks(-0.5), 1000 + 326); // 0.5 rad = 325.95 ticks
    // 0.088 deg per tick (e-manual).
    assert!((RAD_PER_TICK.to_degrees() - 0.0879).abs() < 1e-4);
}

#[test]
fn velocity_unit_is_0_229_rpm() {
    let j = JointCalibration::default();
    // 240 units x 0.229 rev/min = 54.96 rev/min = 5.755 rad/s.
    assert!((j.velocity_to_rad_s(240) - 5.7554).abs() < 1e-3);
}

#[test]
fn load_and_current_to_torque_estimates() {
    // MX-28: 400 = 40.0 % of 2.5 N m = 1.0 N m.
    assert!((load_to_torque_nm(Model::Mx28V2, 400) - 1.0).abs() < 1e-6);
    assert_eq!(load_to_torque_mnm(Model::Mx28V2, 400), 1000);
    // MX-64: 203 x 3.36 mA = 682 mA; x 6.0 N m / 4.1 A = 0.998 N m.
    assert!((load_to_torque_nm(Model::Mx64V2, 203) - 0.998).abs() < 1e-3);
    assert_eq!(load_to_torque_mnm(Model::Mx64V2, 203), 998);
    assert_eq!(torque_to_load(Model::Mx28V2, -1.0), -400);
    assert_eq!(
        torque_to_load(Model::Mx28V2, 10.0),
        1000,
        "MX-28 load saturates at 100 %"
    );
    let j = JointCalibration {
        zero_ticks: 0,
        reversed: true,
    };
    assert!((j.load_to_torque_nm(Model::Mx28V2, 400) + 1.0).abs() < 1e-6);
}

#[test]
fn stiffness_from_p_gain() {
    // (850/128)/885 x 2.5 N m per tick x 4096/(2 pi) ticks/rad = 12.23 N m/rad.
    assert!((stiffness_nm_per_rad(Model::Mx28V2, 850) - 12.23).abs() < 0.01);
    assert!((stiffness_nm_per_rad(Model::Mx64V2, 850) - 29.35).abs() < 0.01);
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
    assert_eq!((Model::Mx28V2.number(), Model::Mx64V2.number()), (30, 311));
}

//! The model's servo maps convert angles and ticks through the project's one converter
//! (`protocol::Calibration`), for the step table and the physics robot alike. Checked against the
//! e-manual (MX(2.0): 4096 ticks a revolution, 0.088 deg a tick, 2048 at the centre) by hand.

use dynamixel::ServoModel;
use planner::model::{ServoMap, builtin};
use planner::plan::gait_table::joint_specs;

fn map(zero_offset: f64, sign: i8) -> ServoMap {
    ServoMap {
        id: 1,
        model: ServoModel::Mx28,
        zero_offset,
        sign,
    }
}

#[test]
fn angle_zero_sits_where_the_e_manual_says() {
    // 0.5 rad is 0.5 x 4096 / 2 pi = 325.95 ticks: angle 0 at 2048 - 325.95 = 1722.05 -> 1722, and
    // on a reversed servo at 2048 + 325.95 = 2373.95 -> 2374.
    assert_eq!(map(0.5, 1).zero_ticks(), 1722);
    assert_eq!(map(0.5, -1).zero_ticks(), 2374);
    assert_eq!(map(0.0, 1).zero_ticks(), 2048);
    // 90 deg = 1024 ticks from the centre; one tick is 0.088 deg (360 / 4096 = 0.08789).
    assert!((map(0.0, 1).angle_of_ticks(3072) - std::f64::consts::FRAC_PI_2).abs() < 1e-6);
    assert!((map(0.0, -1).angle_of_ticks(3072) + std::f64::consts::FRAC_PI_2).abs() < 1e-6);
    assert!((map(0.0, 1).angle_of_ticks(2049).to_degrees() - 0.087_890_6).abs() < 1e-4);
    // Round trip through the zero: the angle at the zero's tick is 0 to within half a tick.
    let m = map(0.5, -1);
    let half_tick = std::f64::consts::PI / 4096.0;
    assert!(m.angle_of_ticks(m.zero_ticks() as i32).abs() <= half_tick);
}

#[test]
fn the_step_tables_zero_is_the_servo_maps() {
    let model = builtin("drosophibot2").unwrap();
    let (idx, specs) = joint_specs(&model).unwrap();
    assert_eq!(specs.len(), 22);
    for (&j, spec) in idx.iter().zip(&specs) {
        let s = model.joints[j].servo.unwrap();
        // Hand: centre - sign zero_offset 4096 / 2 pi, rounded.
        let hand =
            (2048.0 - f64::from(s.sign) * s.zero_offset * 4096.0 / std::f64::consts::TAU).round();
        assert_eq!(
            f64::from(spec.zero_offset),
            hand,
            "{}",
            model.joints[j].name
        );
        assert_eq!(spec.model, s.model, "{}", model.joints[j].name);
    }
}

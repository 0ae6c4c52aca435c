//! The servo-feasibility check against hand calculations: a sinusoid's peak speed A w, the MX
//! datasheet speeds (55 and 63 rev/min at 12 V), the torque-speed line and an injected IK jump.

use planner::model::{Actuation, ActuatorKind, builtin};
use planner::plan::feasibility::{Violation, check, servo_limits};
use std::f64::consts::TAU;

#[test]
fn datasheet_limits() {
    let mx28 = servo_limits(ActuatorKind::Servo(dynamixel::ServoModel::Mx28)).unwrap();
    let mx64 = servo_limits(ActuatorKind::Servo(dynamixel::ServoModel::Mx64)).unwrap();
    // 55 rev/min = 55 * 2 pi / 60 = 5.7596 rad/s; 63 rev/min = 6.5973 rad/s.
    assert!((mx28.no_load_speed - 5.759_586_5).abs() < 1e-5);
    assert!((mx64.no_load_speed - 6.597_344_6).abs() < 1e-5);
    assert_eq!((mx28.stall_torque, mx64.stall_torque), (2.5, 6.0));
    assert_eq!(servo_limits(ActuatorKind::Generic), None);
}

/// Every actuated joint of the robot follows A sin(w t) with n slices per period T.
fn sinusoid(amplitude: f64, period: f64, n: usize) -> (planner::model::Model, Vec<Vec<f64>>, f64) {
    let m = builtin("drosophibot2").unwrap();
    let dt = period / n as f64;
    let q = (0..n)
        .map(|s| {
            m.joints
                .iter()
                .map(|_| amplitude * (TAU * s as f64 / n as f64).sin())
                .collect()
        })
        .collect();
    (m, q, dt)
}

fn actuator(m: &planner::model::Model, name: &str) -> ActuatorKind {
    match m.joints.iter().find(|j| j.name == name).unwrap().actuation {
        Actuation::Actuated { actuator, .. } => actuator,
        Actuation::Fixed { .. } => panic!("{name} is fixed"),
    }
}

#[test]
fn a_sinusoid_at_6_rad_s_is_too_fast_for_an_mx28_only() {
    // Peak speed A w = 0.5 * 2 pi / (pi / 6) = 6.0 rad/s: over the MX-28's 5.76, under the MX-64's
    // 6.60. Peak acceleration A w^2 = 72 rad/s^2. Central differences over 2000 slices agree to
    // 1e-5 relative (sin(w dt) / (w dt)).
    let (m, q, dt) = sinusoid(0.5, TAU / 12.0, 2000);
    let f = check(&m, &q, None, dt);
    for j in &f.joints {
        assert!((j.speed.value - 6.0).abs() < 1e-4, "{}", j.speed.value);
        assert!(
            (j.acceleration.value - 72.0).abs() < 1e-2,
            "{}",
            j.acceleration.value
        );
    }
    let slow: Vec<&str> = f
        .violations
        .iter()
        .map(|v| match v {
            Violation::Speed { joint, limit, .. } => {
                assert!((limit - 5.7596).abs() < 1e-4);
                joint.as_str()
            }
            other => panic!("unexpected {other}"),
        })
        .collect();
    assert!(!slow.is_empty());
    for name in slow {
        assert_eq!(
            actuator(&m, name),
            ActuatorKind::Servo(dynamixel::ServoModel::Mx28),
            "{name}"
        );
    }
    assert!(f.violations[0].to_string().contains("by 0.24 rad/s"));
}

#[test]
fn torque_above_the_torque_speed_line_and_over_stall_are_named() {
    // At the speed peak (t = 0, 6.0 rad/s, MX-64: 6.0 (1 - 6.0 / 6.5973) = 0.543 N m available)
    // a driving torque of 1 N m is 0.457 N m too much; a constant 7 N m is over the 6.0 N m stall.
    let (m, q, dt) = sinusoid(0.5, TAU / 12.0, 2000);
    let ctr = m.joints.iter().position(|j| j.name == "LM_CTr").unwrap();
    let fti = m.joints.iter().position(|j| j.name == "LM_FTi").unwrap();
    let mut torque = vec![vec![0.0; m.joints.len()]; q.len()];
    torque[0][ctr] = 1.0;
    for t in &mut torque {
        t[fti] = -7.0;
    }
    let f = check(&m, &q, Some(&torque), dt);
    let at_speed = f
        .violations
        .iter()
        .find_map(|v| match v {
            Violation::TorqueAtSpeed {
                joint,
                slice,
                available,
                ..
            } if joint == "LM_CTr" => Some((*slice, *available)),
            _ => None,
        })
        .expect("LM_CTr over the torque-speed line");
    assert_eq!(at_speed.0, 0);
    assert!((at_speed.1 - 6.0 * (1.0 - 6.0 / 6.597_344_6)).abs() < 1e-3);
    assert!(f.violations.iter().any(|v| matches!(v,
        Violation::Torque { joint, torque, limit, .. } if joint == "LM_FTi" && *torque == 7.0 && *limit == 2.5)));
}

#[test]
fn an_ik_branch_jump_is_named_with_its_slices() {
    // A slow sinusoid (0.05 rad over 100 slices: steps of at most 0.0031 rad) with a 0.4 rad
    // offset from slice 31 to 59: jumps between 30 -> 31 and 59 -> 60.
    let (m, mut q, dt) = sinusoid(0.05, 4.0, 100);
    for row in q.iter_mut().take(60).skip(31) {
        row[0] += 0.4;
    }
    let f = check(&m, &q, None, dt);
    let jumps: Vec<(usize, f64)> = f
        .violations
        .iter()
        .filter_map(|v| match v {
            Violation::Jump { joint, slice, step } if *joint == m.joints[0].name => {
                Some((*slice, *step))
            }
            _ => None,
        })
        .collect();
    assert_eq!(jumps.iter().map(|j| j.0).collect::<Vec<_>>(), vec![30, 59]);
    assert!(jumps.iter().all(|j| (j.1 - 0.4).abs() < 0.01));
}

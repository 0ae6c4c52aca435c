//! Dimensional analysis as truth: the same path traversed k times faster, without gravity, needs
//! exactly k^2 times the torques and forces (every acceleration and every velocity product scales
//! with k^2), and with gravity the static and inertial parts superpose.

use crate::dynamics_support;
use dynamics_support::{standing_pose, toy_hexapod, trajectory};
use nalgebra::Vector3;
use planner::dynamics::{DynamicsOptions, SliceInput, ThoraxMotion, solve_slice};

#[test]
fn inertial_torques_scale_with_speed_squared() {
    let model = toy_hexapod();
    let q0 = standing_pose(&model);
    for i in 0..5 {
        let t = 0.11 * i as f64;
        let (q, qd, qdd) = trajectory(&model, &q0, t);
        let make = |k: f64, g: Vector3<f64>| {
            let mut s = SliceInput::still(&model, q.clone());
            s.qd = qd.iter().map(|v| v * k).collect();
            s.qdd = qdd.iter().map(|v| v * k * k).collect();
            s.thorax = ThoraxMotion {
                angular_velocity: Vector3::new(0.0, 0.0, 0.2 * k),
                ..Default::default()
            };
            s.gravity = g;
            s.stance = vec![true, false, true, false, true, true];
            s
        };
        let opts = DynamicsOptions::default();
        let slow = solve_slice(&model, &make(1.0, Vector3::zeros()), &opts, i).unwrap();
        let fast = solve_slice(&model, &make(3.0, Vector3::zeros()), &opts, i).unwrap();
        let peak = slow.torque.iter().fold(0.0f64, |m, t| m.max(t.abs()));
        assert!(peak > 0.0);
        for (a, b) in slow.torque.iter().zip(&fast.torque) {
            assert!((9.0 * a - b).abs() < 1e-9 * 9.0 * peak, "{a} * 9 vs {b}");
        }
        // Superposition: without inequalities the optimum is linear in the loads, so gravity
        // plus motion at speed k gives static torques + k^2 times the inertial ones.
        let g = Vector3::new(0.0, 0.0, -9.81);
        let stat = solve_slice(&model, &make(0.0, g), &opts, i).unwrap();
        let both = solve_slice(&model, &make(2.0, g), &opts, i).unwrap();
        for j in 0..model.joints.len() {
            let expect = stat.torque[j] + 4.0 * slow.torque[j];
            assert!(
                (both.torque[j] - expect).abs() < 1e-9 * (peak + 1.0),
                "{} vs {expect}",
                both.torque[j]
            );
        }
    }
}

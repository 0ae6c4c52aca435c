//! The step table written for the board, read back with the protocol crate's own parser: angles,
//! torques and stance survive to the table's resolution, and the servo map agrees with the
//! model's tick formula.

use crate::dynamics_support;
use dynamics_support::{standing_pose, toy_hexapod, trajectory};
use planner::dynamics::{DynamicsOptions, SliceInput, solve_slice};
use planner::model::{Leg, ServoMap};
use planner::plan::gait_table::{TableError, gait_table, stance_bits};
use protocol::GaitTable;

fn with_servos(mut model: planner::model::Model) -> planner::model::Model {
    let mut id = 1;
    for j in &mut model.joints {
        if matches!(j.actuation, planner::model::Actuation::Actuated { .. }) {
            j.servo = Some(ServoMap {
                id,
                model: dynamixel::ServoModel::Mx28,
                zero_offset: 0.1 * f64::from(id % 5) - 0.2,
                sign: if id % 2 == 0 { 1 } else { -1 },
            });
            id += 1;
        }
    }
    model
}

#[test]
fn table_round_trips_through_the_protocol_parser() {
    let model = with_servos(toy_hexapod());
    let q0 = standing_pose(&model);
    let mut q = Vec::new();
    let mut torque = Vec::new();
    let mut stance = Vec::new();
    for s in 0..8 {
        let (qs, qd, qdd) = trajectory(&model, &q0, 0.05 * s as f64);
        let mut input = SliceInput::still(&model, qs.clone());
        input.qd = qd;
        input.qdd = qdd;
        input.stance = (0..6usize).map(|f| s % 2 == 0 || f % 2 == 0).collect();
        let sol = solve_slice(&model, &input, &DynamicsOptions::default(), s).unwrap();
        stance.push(stance_bits(&Leg::ALL, &input.stance));
        q.push(qs);
        torque.push(sol.torque);
    }
    let bytes = gait_table(&model, "toy", 1.25, 0.6, &q, &torque, &stance).unwrap();
    let table = GaitTable::parse(&bytes).unwrap();
    assert_eq!(table.slice_count(), 8);
    let servos: Vec<usize> = (0..model.joints.len())
        .filter(|&j| model.is_actuated(j))
        .collect();
    assert_eq!(table.joint_count(), servos.len());
    for s in 0..8 {
        assert_eq!(table.stance(s), Some(stance[s]));
        for (k, &j) in servos.iter().enumerate() {
            let a = f64::from(table.angle(s, k).unwrap()) * 1e-4;
            let t = f64::from(table.torque(s, k).unwrap()) * 1e-3;
            assert!(
                (a - q[s][j]).abs() <= 0.5e-4 + 1e-12,
                "slice {s} joint {j}: {a} vs {}",
                q[s][j]
            );
            assert!(
                (t - torque[s][j]).abs() <= 0.5e-3 + 1e-12,
                "slice {s} joint {j}: {t} vs {}",
                torque[s][j]
            );
        }
    }
    // The model's map: angle = sign (ticks - 2048) 2 pi / 4096 + zero_offset.
    for (k, &j) in servos.iter().enumerate() {
        let m = model.joints[j].servo.unwrap();
        let map = table.joint(k).unwrap();
        assert_eq!(map.servo_id, m.id);
        for angle in [-1.0, 0.0, 0.7] {
            let ticks = f64::from(map.angle_to_ticks((angle * 1e4) as i32));
            let back = f64::from(m.sign) * (ticks - 2048.0) * std::f64::consts::TAU / 4096.0
                + m.zero_offset;
            assert!(
                (back - angle).abs() < 2.0 * std::f64::consts::TAU / 4096.0,
                "{} at {angle}: {back}",
                model.joints[j].name
            );
        }
    }
}

#[test]
fn a_fly_cannot_become_a_table() {
    let model = toy_hexapod();
    let q = vec![standing_pose(&model)];
    let t = vec![vec![0.0; model.joints.len()]];
    let e = gait_table(&model, "toy", 1.0, 0.6, &q, &t, &[0]).unwrap_err();
    assert!(
        matches!(e, TableError::NoServo { ref joint } if joint == "LF_ThC1"),
        "{e}"
    );
}

//! The firmware library drives the MuJoCo body over the simulated Dynamixel bus: the planner's
//! tripod gait, uploaded and played with the board commands, walks the body forward as planned,
//! and the servos' load registers (`dbot record`'s torque estimate) follow the planned torques,
//! here where they could fail (the virtual robot's lag servos carry the plan by construction).

use crate::support;
use board::record::{Recorder, Until, capture, joints_of_table};
use physics::PhysicsRobot;
use planner::model::builtin;
use planner::terrain::Ground;
use protocol::{Direction, GaitTable};

#[test]
fn the_firmware_walks_the_simulated_robot_as_planned_and_its_loads_follow_the_plan() {
    let model = builtin("drosophibot2").unwrap();
    let (plan, _, table) = support::tripod(&model);
    let robot = PhysicsRobot::drosophibot(&Ground::Flat).unwrap();
    let (start, _) = robot.plant().thorax_pose();
    let steps = 2;
    let mut b = support::walking(robot, &table, Direction::Forward, steps);
    let parsed = GaitTable::parse(&table).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let mut rec =
        Recorder::create(&dir.path().join("walk.csv"), joints_of_table(&parsed, &[])).unwrap();
    let until = Until {
        seconds: None,
        standing: true,
    };
    capture(&mut b, &mut rec, until, |_| {}).unwrap();
    let status = b.status().unwrap();
    assert_eq!(status.fault, None);
    let r = b.transport().robot();
    let (end, quat) = r.servos().plant().thorax_pose();

    // Distance: the plan moves the thorax at translation / stance time for a whole cycle,
    // 0.085 m / 0.75 s * 1.25 s = 0.1417 m per cycle. Measured 0.1456 (+2.8 %): the start ramp
    // and the stop each add a little. Bound 10 %.
    let per_cycle = plan.thorax_velocity.x * plan.period_s;
    let walked = (end[0] - start[0]) / f64::from(steps);
    assert!(
        (walked - per_cycle).abs() < 0.1 * per_cycle,
        "walked {walked} m per cycle, planned {per_cycle}"
    );
    // Height and tilt stay near the plan's standing posture: within 5 mm and 2 degrees.
    assert!(
        (end[2] - start[2]).abs() < 0.005,
        "thorax height {} -> {}",
        start[2],
        end[2]
    );
    let tilt = 2.0 * (quat[1].powi(2) + quat[2].powi(2)).sqrt().asin();
    assert!(tilt < 2f64.to_radians(), "tilt {tilt} rad");

    // Loads against the planned torques over the walking cycles (after the start ramp).
    let rows: Vec<_> = rec
        .rows()
        .iter()
        .filter(|r| r.step >= 1 && r.modelled_nm.is_some())
        .collect();
    assert!(rows.len() > 22 * 100, "{} rows", rows.len());
    let mut per_joint = vec![(0.0, 0.0, 0usize); 22];
    for row in &rows {
        let m = row.modelled_nm.unwrap();
        let e = row.torque_estimate_nm.unwrap();
        let s = &mut per_joint[row.joint];
        s.0 += (e - m).powi(2);
        s.1 += m * m;
        s.2 += 1;
    }
    let (num, den): (f64, f64) = per_joint
        .iter()
        .fold((0.0, 0.0), |a, s| (a.0 + s.0, a.1 + s.1));
    let rel = (num / den).sqrt();
    eprintln!("loads vs plan: relative RMS {rel}");
    for (j, s) in per_joint.iter().enumerate() {
        eprintln!(
            "joint {j:2}: rms diff {:.3} N m, rms plan {:.3}",
            (s.0 / s.2 as f64).sqrt(),
            (s.1 / s.2 as f64).sqrt()
        );
    }
    // Measured 0.33 (worst: the front CTr and FTi, whose swing the quasi-static plan ignores, and
    // the hind CTr). Bound 0.45: a servo model or contact that stopped carrying the body fails it.
    assert!(rel < 0.45, "relative RMS {rel}");
}

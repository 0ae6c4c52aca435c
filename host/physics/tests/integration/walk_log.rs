//! The walk log the demo draws and compares from: a pose every N bus cycles, and each pose rebuilds
//! the simulated body through the planner's forward kinematics (each foot tip one sphere radius
//! from MuJoCo's own foot sphere centre, a rigid offset whatever the pose), slices that follow the
//! gait clock, and foot forces that carry the robot's weight.

use crate::support;
use planner::terrain::Ground;
use std::time::Duration;

use nalgebra::{Isometry3, Point3, Quaternion, Translation3, UnitQuaternion};
use physics::PhysicsRobot;
use planner::kinematics::forward;
use planner::model::{FOOT_RADIUS_M, builtin};
use protocol::Direction;

#[test]
fn logged_poses_rebuild_the_body_and_the_forces_carry_its_weight() {
    let model = builtin("drosophibot2").unwrap();
    let (plan, _, table) = support::tripod(&model);
    let mut robot = PhysicsRobot::drosophibot(&Ground::Flat).unwrap();
    robot.start_log(4);
    let mut b = support::walking(robot, &table, Direction::Forward, 1);
    // The start ramp (2.3 s, each leg pair lifted in turn), then the first step.
    b.wait(Duration::from_millis(4000)).unwrap();
    let servos = b.transport_mut().robot_mut().servos_mut();
    let plant_weight = servos.plant().weight_n();
    let planned_height = servos.planned_height_m();
    let log = servos.take_log().unwrap();
    assert!(servos.take_log().is_none(), "the log is handed over once");
    assert_eq!(log.pose_every, 4);
    // 4 s at the board's 100 Hz bus cycle.
    assert!(
        (390..=410).contains(&log.samples.len()),
        "{}",
        log.samples.len()
    );
    for (i, s) in log.samples.iter().enumerate() {
        assert_eq!(s.pose.is_some(), i % 4 == 0, "sample {i}");
    }
    // The stance the robot is set down in is the plan's resting height (table 1), within 1 mm.
    let start = log.samples[0].thorax.0[2];
    assert!(
        (planned_height - start).abs() < 1e-3,
        "{planned_height} vs {start}"
    );
    // Every pose: the foot tips of forward kinematics sit one foot radius from the sphere centres
    // MuJoCo reports in the same cycle.
    let mut worst = 0.0f64;
    for s in log.samples.iter().filter(|s| s.pose.is_some()) {
        let ([x, y, z], [w, i, j, k]) = s.thorax;
        let thorax = Isometry3::from_parts(
            Translation3::new(x, y, z),
            UnitQuaternion::from_quaternion(Quaternion::new(w, i, j, k)),
        );
        let fk = forward(&model, s.pose.as_ref().unwrap());
        for (f, tip) in model.feet.iter().zip(&fk.feet) {
            let tip: Point3<f64> = thorax * tip;
            let centre = s.foot_spheres.iter().find(|(l, _)| *l == f.leg).unwrap().1;
            let d = (tip - Point3::from(centre)).norm();
            // MuJoCo's world positions are from the forward pass before the last step's
            // integration, the joint angles after it: 1 ms apart, so a foot swinging at up to
            // 0.6 m/s is up to 0.6 mm off (measured: 0.67 mm at most, about 1 um standing). A foot
            // drawn on the wrong body or frame would be centimetres off.
            let e = (d - FOOT_RADIUS_M).abs();
            assert!(e < 1e-3, "{:?} at {} s: {d} m", f.leg, s.time_s);
            worst = worst.max(e);
        }
    }
    eprintln!("largest foot offset error {worst} m");
    // Walking, the slices follow the gait clock: 100 slices in the 2.5 s period, forward.
    let walking: Vec<_> = log.samples.iter().filter(|s| s.walking).collect();
    assert!(walking.len() > 100, "{}", walking.len());
    let n = plan.slices() as f64;
    for w in walking.windows(2) {
        let (a, b) = (w[0].playback.unwrap().1, w[1].playback.unwrap().1);
        let dt = w[1].time_s - w[0].time_s;
        let expected = dt / plan.period_s * n;
        let moved = (f64::from(b) - f64::from(a)).rem_euclid(n);
        assert!(
            (moved - expected).abs() <= 1.0,
            "slice {a} -> {b} in {dt} s"
        );
    }
    // Once the full weight is on the feet (gravity ramps in over 1 s) and while the robot walks
    // slowly, the vertical foot forces carry it: within 5 % on average (the body accelerates a
    // little).
    let late: Vec<f64> = log
        .samples
        .iter()
        .filter(|s| s.time_s > 2.0)
        .map(|s| s.foot_forces.iter().map(|(_, f)| f[2]).sum())
        .collect();
    let mean = late.iter().sum::<f64>() / late.len() as f64;
    assert!(
        (mean / plant_weight - 1.0).abs() < 0.05,
        "{mean} N vs {plant_weight} N"
    );
}

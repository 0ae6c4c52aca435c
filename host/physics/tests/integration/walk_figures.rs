//! The walk's figures (two tripod cycles from power-on, firmware in the loop): stable under a
//! halved timestep, and a robot too weak for its gait sags and the report names the joints.

use crate::support;
use physics::PhysicsRobot;
use planner::model::builtin;
use planner::terrain::Ground;

#[test]
fn halving_the_timestep_changes_the_walk_figures_little() {
    let model = builtin("drosophibot2").unwrap();
    let (_, _, table) = support::tripod(&model);
    let mut fig = Vec::new();
    // The physics robot's timestep (1 ms) and half of it.
    for dt in [physics::TIMESTEP_S, 0.5 * physics::TIMESTEP_S] {
        let mut options = PhysicsRobot::options(&model, &Ground::Flat).unwrap();
        options.timestep_s = dt;
        let robot = PhysicsRobot::with_options(&model, &options, &Ground::Flat).unwrap();
        fig.push(support::walk_figures(robot, &table, 2));
    }
    let (a, b) = (&fig[0], &fig[1]);
    eprintln!("1 ms: {a:?}\n0.5 ms: {b:?}");
    // The robot carries the planned gait: no sag beyond 1 cm, no fall.
    assert_eq!(a.verdict(0.01), None, "{a:?}");
    // Bounds (measured differences, 1 ms against 0.5 ms, in brackets): distance 2 % (0.5 %),
    // heading 0.02 rad (0.014), lowest thorax height 1.5 mm (1.1), largest tilt 1 deg (0.62),
    // slip per foot 4 mm (2.3, LH). Before the embed merge 0.5 ms against 0.25 ms differed by
    // 0.06 %, 0.005 rad, 0.35 mm, 0.2 deg and 0.7 mm: the 1 ms step is coarser in the transient
    // figures (heading, largest tilt, slip, lowest height), not in distance; the heading after two
    // cycles also moved by 0.013 rad at 0.5 ms when the merge changed the firmware's timing.
    assert!((a.forward_m - b.forward_m).abs() < 0.02 * a.forward_m.abs());
    assert!((a.heading_rad - b.heading_rad).abs() < 0.02);
    assert!((a.height_min_m - b.height_min_m).abs() < 0.0015);
    assert!((a.tilt_max_rad - b.tilt_max_rad).abs() < 1f64.to_radians());
    for ((leg, sa), (_, sb)) in a.slip_m.iter().zip(&b.slip_m) {
        assert!((sa - sb).abs() < 0.004, "{leg:?}: slip {sa} vs {sb} m");
    }
}

#[test]
fn servos_too_weak_for_the_gait_let_the_robot_sag_and_the_report_names_them() {
    let model = builtin("drosophibot2").unwrap();
    let (_, torques, table) = support::tripod(&model);
    let mut robot = PhysicsRobot::drosophibot(&Ground::Flat).unwrap();
    // The middle legs' CTr servos (MX-64, 6 N m) cut to half the planned peak torque.
    for i in 0..robot.plant().joints().len() {
        let j = robot.plant().joints()[i].clone();
        if j.name == "LM_CTr" || j.name == "RM_CTr" {
            let peak = torques
                .iter()
                .map(|row| row[j.joint].abs())
                .fold(0.0, f64::max);
            robot.plant_mut().set_stall(i, 0.5 * peak);
        }
    }
    let weak = support::walk_figures(robot, &table, 2);
    // Measured: the thorax drops 21 mm (the full-strength robot: 4 mm).
    let verdict = weak
        .verdict(0.01)
        .unwrap_or_else(|| panic!("no sag reported: {weak:?}"));
    assert!(weak.height_start_m - weak.height_min_m > 0.015, "{weak:?}");
    assert!(
        verdict.contains("LM_CTr") && verdict.contains("RM_CTr"),
        "{verdict}"
    );
    // Full-strength servos are not blamed.
    assert!(
        !verdict.contains("LF_") && !verdict.contains("RH_"),
        "{verdict}"
    );
}

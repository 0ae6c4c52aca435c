//! The physics servo with the model's servo dynamics, in MuJoCo, against hand-worked cases: the
//! torque-speed line at full duty, no torque for a goal inside the deadband, a push from the
//! middle of the backlash and a reversal that crosses it before the output is driven, and the
//! MJCF's damping, frictionloss and armature in MuJoCo's own model.
//!
//! One joint (LF_CTr, an MX-64) holds with the torque on; the others stay off, so gravity never
//! ramps in (the plant waits for every servo) and nothing else pushes the floating body.

use physics::{PhysicsRobot, Plant};
use planner::model::{Model, ServoParamsEntry, builtin};
use planner::terrain::Ground;

/// Drosophibot II with `entry` over LF_CTr's servo dynamics, its plant, and the joint's index.
fn plant_with(entry: ServoParamsEntry) -> (Model, Plant, usize) {
    let mut model = builtin("drosophibot2").unwrap();
    model.servo_dynamics.set_joint("LF_CTr", entry);
    let options = PhysicsRobot::options(&model, &Ground::Flat).unwrap();
    let plant = Plant::new(&model, &options).unwrap();
    let i = plant
        .joints()
        .iter()
        .position(|j| j.name == "LF_CTr")
        .unwrap();
    (model, plant, i)
}

#[test]
fn at_full_duty_the_torque_follows_the_torque_speed_line() {
    // Stall 5 N m, no-load speed 4 rad/s: the line is 5 (1 - w / 4) N m, kv = 1.25 N m s/rad.
    let (_, mut plant, i) = plant_with(ServoParamsEntry {
        stall_torque_nm: Some(5.0),
        no_load_speed_rad_s: Some(4.0),
        ..Default::default()
    });
    let q0 = plant.joint_state(i).0;
    // 0.5 rad away at 34.3 N m/rad asks 17 N m: saturated at full duty for the first steps.
    plant.set_goal(i, q0 + 0.5, true);
    let mut checked = 0;
    for _ in 0..40 {
        let (q, qd, _) = plant.joint_state(i);
        plant.step();
        let force = plant.joint_state(i).2;
        if plant.joints()[i].kp * (q0 + 0.5 - q) > 5.0 {
            let line = 5.0 * (1.0 - qd / 4.0);
            assert!(
                (force - line).abs() < 1e-9,
                "at {qd} rad/s: {force} N m, line {line}"
            );
            checked += 1;
        }
    }
    assert!(checked > 10, "{checked}");
    assert!(plant.joint_state(i).1 > 1.0, "it got moving");
}

#[test]
fn a_goal_inside_the_deadband_gives_no_torque() {
    // Deadband 0.01 rad: 0.008 rad away nothing; 0.03 rad away the error counts as 0.02 rad,
    // kp x 0.02 = 34.29 x 0.02 = 0.686 N m (the body still, so no back-EMF).
    let (_, mut plant, i) = plant_with(ServoParamsEntry {
        deadband_rad: Some(0.01),
        ..Default::default()
    });
    let q0 = plant.joint_state(i).0;
    // (The floating body is still but for the contacts' settling: allow 1e-9.)
    plant.set_goal(i, q0 + 0.008, true);
    plant.step();
    assert!(
        plant.joint_state(i).2.abs() < 1e-9,
        "{:?}",
        plant.joint_state(i)
    );
    plant.set_goal(i, q0 + 0.03, true);
    plant.step();
    let kp = plant.joints()[i].kp;
    assert!((plant.joint_state(i).2 - kp * 0.02).abs() < 1e-6);
}

#[test]
fn a_push_and_a_reversal_cross_the_backlash_before_the_output_is_driven() {
    // Backlash 0.02 rad (motor in the middle at power-on), MX-64 at 34.29 N m/rad, 6 N m stall,
    // no-load 6.597 rad/s, 1 ms steps. A goal 0.1 rad ahead: duty 34.29 x 0.1 / 6 = 0.5714, the
    // free motor turns at 0.5714 x 6.597 = 3.770 rad/s and closes the 0.01 rad to the output in
    // 2.65 ms: 3 steps with no actuator force at all and the output still, then it is driven.
    let (_, mut plant, i) = plant_with(ServoParamsEntry {
        backlash_rad: Some(0.02),
        ..Default::default()
    });
    let h = plant.timestep();
    assert_eq!(h, physics::TIMESTEP_S);
    let q0 = plant.joint_state(i).0;
    plant.set_goal(i, q0 + 0.1, true);
    let mut still = 0;
    loop {
        plant.step();
        let (q, _, force) = plant.joint_state(i);
        if force != 0.0 {
            break;
        }
        assert!((q - q0).abs() < 1e-9, "moved {} rad undriven", q - q0);
        still += 1;
        assert!(still < 100);
    }
    assert_eq!(still, 3);
    // Push hard (full duty) for 30 ms, then reverse at full duty: the gears part and the free
    // motor crosses the 0.02 rad play at the no-load speed less the output's own speed w:
    // 0.02 / (6.597 + w) s; w < 6.597 rad/s, so between 1.5 and 3.03 ms: 1 to 4 steps without
    // actuator force (the output coasting), then driven backward.
    let q1 = plant.joint_state(i).0;
    plant.set_goal(i, q1 + 0.5, true);
    for _ in 0..30 {
        plant.step();
    }
    let (q2, w, _) = plant.joint_state(i);
    assert!(w > 0.5 && w < 6.6, "{w}");
    plant.set_goal(i, q2 - 0.5, true);
    let mut apart = 0;
    loop {
        plant.step();
        let force = plant.joint_state(i).2;
        if force != 0.0 {
            assert!(force < 0.0, "driven backward: {force}");
            break;
        }
        apart += 1;
        assert!(apart < 100);
    }
    let expected = 0.02 / (6.597 + w) / h;
    assert!(
        (apart as f64 - expected).abs() <= 1.0,
        "{apart} steps apart, {expected:.2} expected"
    );
}

#[test]
fn mujoco_holds_the_models_damping_frictionloss_and_armature() {
    let (model, plant, i) = plant_with(ServoParamsEntry {
        damping_nm_s_per_rad: Some(0.02),
        friction_nm: Some(0.1),
        armature_kg_m2: Some(0.01),
        ..Default::default()
    });
    let _ = (model, i);
    let (damping, friction, armature) = plant.joint_gear("LF_CTr").unwrap();
    assert_eq!((damping, friction, armature), (0.02, 0.1, 0.01));
    // RF_CTr keeps the MX-64's defaults: no damping or friction, 2 g cm^2 x 200^2 of armature.
    let (damping, friction, armature) = plant.joint_gear("RF_CTr").unwrap();
    assert_eq!((damping, friction), (0.0, 0.0));
    assert!((armature - 0.008).abs() < 1e-15);
}

//! The servo's Position P Gain register sets the simulated actuator's stiffness (issue 17): the
//! physics robot reads the register every bus cycle. Against a hand calculation: standing still,
//! a joint's deflection from its goal times the stiffness the e-manual's P controller gives
//! (k = P/128 / 885 * stall torque * 4096 / 2 pi) is its torque, and halving every servo's gain
//! doubles the deflection under the same load (tau = k * dtheta). Every gain is halved, not one:
//! the stance's load distribution depends on the joints' stiffnesses relative to each other, so
//! it stays as it was (to first order; the body sags twice as far, which moves it slightly).
//! This test writes the register on the chain, as a servo tool on the bus would; `set_stiffness.rs`
//! has the firmware write it (`SetStiffness`, `dbot set --stiffness`) through the whole stack.

use crate::support;
use board::robot::{FLASH_SECTORS, SLOTS, ServoDynamics, VirtualFlash, robot_chain};
use dynamixel::control_table as ct;
use firmware::controller::{Config, Controller};
use physics::PhysicsRobot;
use physics::servo::{RAD_PER_TICK, ticks_to_angle};
use planner::terrain::Ground;
use support::hand_k;

#[test]
fn halving_the_p_gain_register_doubles_a_joints_deflection_under_its_load() {
    let mut robot = PhysicsRobot::drosophibot(&Ground::Flat).unwrap();
    let mut chain = robot_chain(Config::default().baud);
    robot.power_on(&mut chain);
    let controller = Controller::new(VirtualFlash::new(FLASH_SECTORS), SLOTS, Config::default());
    // Hold the planner's stance: each goal is the stance angle in ticks, torque on.
    let joints = robot.plant().joints().to_vec();
    for j in &joints {
        let ticks = 2048.0 + f64::from(j.map.sign) * (j.goal - j.map.zero_offset) / RAD_PER_TICK;
        let s = chain.servo_mut(j.map.id).unwrap();
        s.put(ct::GOAL_POSITION, ticks.round() as u32);
        s.put(ct::TORQUE_ENABLE, 1);
    }
    let mut now_us = 0;
    let mut run = |robot: &mut PhysicsRobot, chain: &mut dynamixel::sim::VirtualChain, s: f64| {
        let end = now_us + (s * 1e6) as u64;
        while now_us < end {
            robot.before_cycle(&controller, chain, now_us);
            now_us += 10_000;
        }
    };
    // (deflection goal - angle, rad; torque, N m) of every joint, and its P gain register.
    let measure = |robot: &PhysicsRobot, chain: &dynamixel::sim::VirtualChain| {
        joints
            .iter()
            .enumerate()
            .map(|(i, j)| {
                let s = chain.servo(j.map.id).unwrap();
                let goal = ticks_to_angle(&j.map, s.get(ct::GOAL_POSITION) as i32);
                let (q, _, tau) = robot.plant().joint_state(i);
                (goal - q, tau, s.get(ct::POSITION_P_GAIN))
            })
            .collect::<Vec<_>>()
    };
    run(&mut robot, &mut chain, 3.0);
    assert!(robot.plant().full_gravity());
    let before = measure(&robot, &chain);
    // The most loaded joint carries "the" static load.
    let (x, _) = before
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.1.abs().total_cmp(&b.1.1.abs()))
        .unwrap();
    for j in &joints {
        let s = chain.servo_mut(j.map.id).unwrap();
        let p = s.get(ct::POSITION_P_GAIN);
        s.put(ct::POSITION_P_GAIN, p / 2);
    }
    run(&mut robot, &mut chain, 2.0);
    let after = measure(&robot, &chain);
    let name = &joints[x].name;
    let kind = joints[x].map.model;
    support::assert_torque_is_k_times_deflection(name, kind, before[x], after[x]);
    assert!(
        (robot.plant().joints()[x].kp - hand_k(kind, after[x].2)).abs() < 1e-4,
        "{name}: the plant's kp follows the register"
    );
    let (d1, t1, p1) = before[x];
    let (d2, t2, p2) = after[x];
    assert_eq!(p2, p1 / 2, "{name}: the register was halved");
    let ratio = d2 / d1;
    eprintln!(
        "{name}: P {p1} -> {p2}, torque {t1:.4} -> {t2:.4} N m, deflection {:.3} -> {:.3} mrad, ratio {ratio:.4}",
        d1 * 1e3,
        d2 * 1e3
    );
    // Measured (1 ms, this test's output): RM_CTr, P 993 -> 496, 0.629 -> 0.632 N m, 18.35 ->
    // 36.90 mrad, ratio 2.011: 0.2 % of it is 993 / 2 rounding down to 496, 0.4 % the load the
    // deeper sag moves onto this joint. Bound 2 % (0.04 on the ratio).
    assert!(
        (ratio - 2.0).abs() < 0.04,
        "{name}: deflection ratio {ratio}"
    );
}

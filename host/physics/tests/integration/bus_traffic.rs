//! The body is stepped on simulated time alone: what goes over the bus (how many bytes, how many
//! reads) must not move it. A second master on the robot's wire reads a register after every bus
//! cycle (as the bring-up check's U2D2 would); the same walk with and without those reads gives
//! the same body, bit for bit.

use crate::support;
use dynamixel::control_table::PRESENT_TEMPERATURE;
use dynamixel::master::MasterConfig;
use physics::PhysicsRobot;
use planner::model::builtin;
use planner::terrain::Ground;
use protocol::{PlayCommand, Steps};

/// Thorax pose and every joint's (angle, velocity, torque) after each bus cycle of the first
/// `cycles` cycles of a walk, with a register read by a second master after each cycle or not.
fn walk(table: &[u8], cycles: usize, extra_reads: bool) -> (Vec<[f64; 7]>, Vec<Vec<f64>>, u64) {
    let robot = PhysicsRobot::drosophibot(&Ground::Flat).unwrap();
    let mut b = board::link::Board::connect(robot.into_transport()).unwrap();
    support::gate::upload(&mut b, 0, table).unwrap();
    support::gate::play(&mut b, PlayCommand::forward(0, Steps::Count(1))).unwrap();
    let r = b.transport_mut().robot_mut();
    let wire = r.wire();
    let mut second = wire.master(MasterConfig {
        baud: 1_000_000,
        reply_slack_us: 300,
    });
    let (mut poses, mut joints) = (Vec::new(), Vec::new());
    for _ in 0..cycles {
        r.cycle();
        if extra_reads {
            let mut out = [0u8; 1];
            let read = second.read(1, PRESENT_TEMPERATURE.addr, &mut out);
            wire.block_on(read).unwrap();
        }
        let plant = r.servos().plant();
        let (p, q) = plant.thorax_pose();
        poses.push([p[0], p[1], p[2], q[0], q[1], q[2], q[3]]);
        joints.push(
            (0..plant.joints().len())
                .flat_map(|i| {
                    let (q, qd, tau) = plant.joint_state(i);
                    [q, qd, tau]
                })
                .collect(),
        );
    }
    (poses, joints, r.bus_bytes().0)
}

#[test]
fn extra_bus_traffic_leaves_the_body_unchanged() {
    let model = builtin("drosophibot2").unwrap();
    let (_, _, table) = support::tripod(&model);
    // 3 s at 100 Hz: the start ramp (2.3 s, each leg pair lifted in turn), gravity ramping in,
    // the first swing.
    let cycles = 300;
    let (poses, joints, bytes) = walk(&table, cycles, false);
    let (poses_read, joints_read, bytes_read) = walk(&table, cycles, true);
    // The reads went over the bus: 14 bytes each to the servos (header 4, ID, length 2, instruction, address 2, count 2, CRC 2).
    assert_eq!(bytes_read - bytes, 14 * cycles as u64);
    // The body moved (the walk started) ...
    let moved = (poses[cycles - 1][0] - poses[0][0]).abs();
    assert!(moved > 0.01, "the thorax moved {moved} m");
    // ... and moved identically.
    for k in 0..cycles {
        assert_eq!(poses[k], poses_read[k], "thorax pose after cycle {k}");
        assert_eq!(joints[k], joints_read[k], "joint states after cycle {k}");
    }
}

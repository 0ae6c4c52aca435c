//! Shared by the physics tests: the planner's tripod gait of Drosophibot II as a step table, and a
//! physics robot walking it under the firmware.

#![allow(dead_code)]

use board::link::Board;
use dynamixel::ServoModel;
use physics::{PhysicsRobot, PhysicsTransport};
use planner::dynamics::{DynamicsOptions, solve_cycle};
use planner::gait::StepParams;
use planner::model::Model;
use planner::plan::Plan;
use protocol::{Direction, PlayCommand, Steps};

/// The e-manual's stiffness for P gain `p`, N m/rad (MX-28 2.5 N m, MX-64 6.0 N m stall):
/// k = P/128 / 885 x stall torque x 4096 / 2 pi, from the MX position P controller.
pub fn hand_k(kind: ServoModel, p: u32) -> f64 {
    let stall = match kind {
        ServoModel::Mx28 => 2.5,
        ServoModel::Mx64 => 6.0,
    };
    f64::from(p) / 128.0 / 885.0 * stall * 4096.0 / std::f64::consts::TAU
}

/// At rest a joint's actuator torque is k (goal - q), its stiffness k the register's: checks it,
/// to 1 %, for a joint's (deflection rad, torque N m, P gain) before and after a gain change.
pub fn assert_torque_is_k_times_deflection(
    name: &str,
    kind: ServoModel,
    before: (f64, f64, u32),
    after: (f64, f64, u32),
) {
    for (when, (d, tau, p)) in [("before", before), ("after", after)] {
        let k = hand_k(kind, p);
        assert!(
            (tau - k * d).abs() < 0.01 * tau.abs(),
            "{name} {when}: torque {tau} N m, k {k} N m/rad (P {p}) x deflection {d} rad"
        );
    }
}

/// The paper's table-1 tripod plan for Drosophibot II, its solved torques and its step table.
pub fn tripod(model: &Model) -> (Plan, Vec<Vec<f64>>, Vec<u8>) {
    let params = StepParams::table1(&model.name);
    let plan = planner::plan::plan(model, &params).unwrap();
    let inputs = planner::dynamics::plan_inputs(&plan);
    let cycle = solve_cycle(model, &inputs, &DynamicsOptions::default()).unwrap();
    let torques = planner::dynamics::output::torque_rows(&cycle);
    let table = planner::plan::table::step_table(&plan, Some(&torques), "dbII tripod").unwrap();
    (plan, torques, table)
}

/// A board on `robot` with `table` in slot 0, playing `steps` steps in `direction`.
pub fn walking(
    robot: PhysicsRobot,
    table: &[u8],
    direction: Direction,
    steps: u32,
) -> Board<PhysicsTransport> {
    let mut b = Board::connect(robot.into_transport()).unwrap();
    gate::upload(&mut b, 0, table).unwrap();
    gate::play(
        &mut b,
        PlayCommand {
            slot: 0,
            direction,
            period_scale: 1000,
            steps: Steps::Count(steps),
        },
    )
    .unwrap();
    b
}

/// Walks `steps` cycles forward from power-on (gravity ramps in over the first second after the
/// start ramp switches the servos on) and returns what the body did, measured from the planned
/// stance the robot powers on in.
pub fn walk_figures(robot: PhysicsRobot, table: &[u8], steps: u32) -> physics::Figures {
    use std::time::Duration;
    let mut b = Board::connect(robot.into_transport()).unwrap();
    gate::upload(&mut b, 0, table).unwrap();
    gate::play(&mut b, PlayCommand::forward(0, Steps::Count(steps))).unwrap();
    // The walk takes `steps` periods after a start ramp of well under a period; a robot that
    // faults (e.g. a servo that cannot follow) ends it early.
    for _ in 0..(steps + 2) * 5 {
        b.wait(Duration::from_millis(250)).unwrap();
        let s = b.status().unwrap();
        if s.fault.is_some() || (s.playback.is_none() && s.state == protocol::RunState::Standing) {
            break;
        }
    }
    b.transport().robot().servos().figures().unwrap().clone()
}

pub use crate::gate;

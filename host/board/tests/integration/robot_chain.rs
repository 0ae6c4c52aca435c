//! The virtual robot's servo chain is fixed, as a robot's is (issue #19 item 8): a table naming a
//! servo the robot does not have must not walk, and the chain must not grow the missing servo.

use std::time::Duration;

use board::link::Board;
use board::robot::{VirtualRobot, VirtualTransport};
use firmware::testkit::SyntheticGait;
use protocol::{PlayCommand, RunState, Steps};

fn play() -> PlayCommand {
    PlayCommand::forward(0, Steps::Count(2))
}

fn chain_ids(b: &Board<VirtualTransport>) -> Vec<u8> {
    b.transport()
        .robot()
        .with_chain(|c| c.servos().iter().map(|s| s.id()).collect())
}

#[test]
fn a_table_naming_a_servo_the_robot_lacks_does_not_walk() {
    let mut b = Board::connect(VirtualTransport::new(VirtualRobot::new())).unwrap();
    let mut gait = SyntheticGait::new(100, 1.0);
    // Joint 4 (LF_FTi) on servo 40: no such servo on the bus (IDs 1..=22).
    gait.joints[4].servo_id = 40;
    gate::upload(&mut b, 0, &gait.build()).unwrap();
    let refused = gate::play(&mut b, play());
    b.wait(Duration::from_secs(1)).unwrap();
    let status = b.status().unwrap();
    assert!(
        refused.is_err() || status.state == RunState::Fault,
        "play {refused:?}, then {:?}: a robot without servo 40 must not walk",
        status.state
    );
    assert_ne!(status.state, RunState::Walking);
    assert_eq!(
        chain_ids(&b),
        (1..=22).collect::<Vec<u8>>(),
        "the chain is fixed"
    );
}

#[test]
fn the_robots_own_table_walks_on_the_same_chain() {
    // The control case: the same gait with the robot's IDs plays.
    let mut b = Board::connect(VirtualTransport::new(VirtualRobot::new())).unwrap();
    gate::upload(&mut b, 0, &SyntheticGait::new(100, 1.0).build()).unwrap();
    gate::play(&mut b, play()).unwrap();
    b.wait(Duration::from_millis(1500)).unwrap();
    assert_eq!(b.status().unwrap().state, RunState::Walking);
    assert_eq!(chain_ids(&b), (1..=22).collect::<Vec<u8>>());
}

/// Which joint carries which servo comes from the model file: the virtual robot's chain holds, at
/// each joint's ID, the servo model the file names for that joint. Independent truth: the paper
/// (and the robot's build sheet) puts MX-64(2.0) on the six CTr joints, MX-28(2.0) on the other 16.
#[test]
fn the_chain_carries_the_servos_the_model_file_names() {
    let model = planner::model::builtin("drosophibot2").unwrap();
    let b = Board::connect(VirtualTransport::new(VirtualRobot::new())).unwrap();
    let on_bus: Vec<(u8, dynamixel::ServoModel)> = b
        .transport()
        .robot()
        .with_chain(|c| c.servos().iter().map(|s| (s.id(), s.model())).collect());
    let mut mx64 = 0;
    for j in &model.joints {
        let Some(map) = j.servo else { continue };
        let found = on_bus.iter().find(|(id, _)| *id == map.id);
        assert_eq!(found.map(|f| f.1), Some(map.model), "{}", j.name);
        let paper = if j.kind == planner::model::JointKind::CTr {
            mx64 += 1;
            dynamixel::ServoModel::Mx64
        } else {
            dynamixel::ServoModel::Mx28
        };
        assert_eq!(map.model, paper, "{}", j.name);
    }
    assert_eq!((on_bus.len(), mx64), (22, 6));
}

use crate::gate;

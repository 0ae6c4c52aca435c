//! Gait switching on the virtual robot (the firmware's own board over the simulated bus): forward,
//! a turning variant, backward and stop as one run queued through `Board::queue_gait`, with no
//! fault, no stand in between, and the slot / step sequence as queued.

use std::f64::consts::PI;
use std::time::Duration;

use board::link::Board;
use board::robot::{VirtualRobot, VirtualTransport};
use firmware::testkit::{JOINTS, SyntheticGait};
use protocol::gait::GaitTableBuilder;
use protocol::{Direction, PlayCommand, QueueCommand, RunState, Steps};

/// The synthetic gait with 0.05 sin(2 pi s / slices) rad added to every angle: the same slice 0
/// (and tripod), so it may follow the synthetic gait at a step boundary. An estimate stand-in for a
/// planned curve: the switch rule only looks at the boundary slices.
fn turn(g: &SyntheticGait) -> Vec<u8> {
    let mut b = GaitTableBuilder::new("turn", g.period_s, 0.5, g.joints.clone());
    for s in 0..g.slices {
        let extra = 0.05 * (2.0 * PI * s as f64 / g.slices as f64).sin();
        let angles: Vec<f64> = (0..JOINTS).map(|j| g.angle(s, j) + extra).collect();
        let torques: Vec<f64> = (0..JOINTS).map(|j| g.torque(s, j)).collect();
        b.slice(
            if s < 50 { 0b010_101 } else { 0b101_010 },
            &angles,
            &torques,
        );
    }
    b.build().unwrap()
}

fn queued(slot: u8, direction: Direction) -> QueueCommand {
    QueueCommand(PlayCommand::new(slot, direction, 1000, Steps::Count(2)))
}

#[test]
fn forward_turn_backward_and_stop_play_as_one_run() {
    let mut b = Board::connect(VirtualTransport::new(VirtualRobot::new())).unwrap();
    let g = SyntheticGait::new(100, 1.0);
    gate::upload(&mut b, 0, &g.build()).unwrap();
    gate::upload(&mut b, 1, &turn(&g)).unwrap();
    gate::play(&mut b, PlayCommand::forward(0, Steps::Count(2))).unwrap();
    gate::queue(&mut b, queued(1, Direction::Forward)).unwrap();
    gate::queue(&mut b, queued(0, Direction::Backward)).unwrap();
    // Ramp (at least 0.5 s) plus 3 x 2 steps of 1 s; status every 0.1 s.
    let mut seen: Vec<(u8, Direction)> = vec![];
    let mut walked = false;
    for _ in 0..120 {
        b.wait(Duration::from_millis(100)).unwrap();
        let st = b.status().unwrap();
        assert!(st.fault.is_none(), "fault {:?}", st.fault);
        if let Some(p) = st.playback {
            walked = true;
            if seen.last() != Some(&(p.slot, p.direction)) {
                seen.push((p.slot, p.direction));
            }
        }
        if walked {
            assert_ne!(st.state, RunState::Ramping, "no second ramp between gaits");
            if st.state == RunState::Standing {
                break;
            }
        }
    }
    assert_eq!(
        seen,
        [
            (0, Direction::Forward),
            (1, Direction::Forward),
            (0, Direction::Backward)
        ]
    );
    let st = b.status().unwrap();
    assert_eq!(st.state, RunState::Standing);
    // The step count runs on across the switches: 2 + 2 + 2.
    // Standing sends telemetry on: switch it off, then read what is kept (bounded).
    b.set_telemetry(0).unwrap();
    let mut steps = vec![];
    for _ in 0..5000 {
        let Some(t) = b.telemetry(Duration::from_millis(20)).unwrap() else {
            break;
        };
        if steps.last() != Some(&t.step) {
            steps.push(t.step);
        }
    }
    assert_eq!(
        steps.iter().max(),
        Some(&6),
        "steps in the telemetry: {steps:?}"
    );
}

use crate::gate;

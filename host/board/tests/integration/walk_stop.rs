//! The one stop path (`board::record::stop_walk`) on the virtual robot, simulated time: a stop in
//! the start ramp holds the robot where the ramp got to and a recording until standing ends
//! (issue 30 item 3: `record --play` recorded on, forever, after Ctrl-C in the ramp); a stop
//! while walking finishes the step; a stop while standing has nothing to stop.

use std::time::Duration;

use board::link::Board;
use board::record::{Ended, Recorder, Stopped, capture_until_standing, joints_of_table, stop_walk};
use board::robot::{VirtualRobot, VirtualTransport};
use firmware::testkit::SyntheticGait;
use protocol::{GaitTable, PlayCommand, RunState, Steps};

/// A board walking an endless 0.6 s gait, `after` board time after the play command.
fn walking(gait: &[u8], after: Duration) -> Board<VirtualTransport> {
    let mut b = Board::connect(VirtualTransport::new(VirtualRobot::new())).unwrap();
    gate::upload(&mut b, 0, gait).unwrap();
    b.set_telemetry(1).unwrap();
    gate::play(&mut b, PlayCommand::forward(0, Steps::Continuous)).unwrap();
    b.wait(after).unwrap();
    // The recording starts now (the records kept while waiting are not its own).
    b.discard_telemetry();
    b
}

/// What a command does on Ctrl-C: stop, then record until the robot stands. The recording must
/// end within `bound_s` of board time after the stop.
fn stop_and_record(b: &mut Board<VirtualTransport>, gait: &[u8], bound_s: f64) -> Stopped {
    let table = GaitTable::parse(gait).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let mut rec =
        Recorder::create(&dir.path().join("t.csv"), joints_of_table(&table, &[])).unwrap();
    let how = stop_walk(b).unwrap();
    let ended = capture_until_standing(b, &mut rec, |t| {
        assert!(
            t < bound_s,
            "still recording {t:.1} s after the stop ({how:?}): the robot stands, the recording must end"
        );
    })
    .unwrap();
    assert_eq!(ended, Ended::Done);
    how
}

#[test]
fn a_stop_in_the_ramp_holds_the_robot_and_the_recording_ends() {
    let gait = SyntheticGait::new(40, 0.6).build();
    // The ramp lasts at least 0.5 s (firmware `Config::ramp_min_us`): at 0.1 s it is under way.
    let mut b = walking(&gait, Duration::from_millis(100));
    assert_eq!(b.status().unwrap().state, RunState::Ramping);
    // A robot that holds stands at once: one state poll (0.2 s) is enough.
    assert_eq!(stop_and_record(&mut b, &gait, 0.5), Stopped::RampHeld);
    assert_eq!(b.status().unwrap().state, RunState::Standing);
    // And stays: 3 s later (five steps' worth) it has not started walking.
    b.wait(Duration::from_secs(3)).unwrap();
    let st = b.status().unwrap();
    assert_eq!(st.state, RunState::Standing);
    assert_eq!(st.playback.map_or(0, |p| p.step), 0);
}

#[test]
fn a_stop_while_walking_finishes_the_step() {
    let gait = SyntheticGait::new(40, 0.6).build();
    // 2 s: the ramp is over and the robot walks.
    let mut b = walking(&gait, Duration::from_secs(2));
    assert_eq!(b.status().unwrap().state, RunState::Walking);
    // The rest of one 0.6 s step, plus a state poll.
    // At most the rest of one 0.6 s step, then one state poll (0.2 s), then a bus cycle.
    assert_eq!(stop_and_record(&mut b, &gait, 0.81), Stopped::AtEndOfStep);
    assert_eq!(b.status().unwrap().state, RunState::Standing);
}

#[test]
fn a_stop_while_standing_has_nothing_to_stop() {
    let mut b = Board::connect(VirtualTransport::new(VirtualRobot::new())).unwrap();
    b.wait(Duration::from_millis(100)).unwrap();
    let how = stop_walk(&mut b).unwrap();
    assert_eq!(how, Stopped::NotWalking);
    assert_eq!(how.describe(), "the robot was not walking");
}

#[test]
fn a_stop_on_a_board_in_a_fault_has_nothing_to_stop() {
    // A servo that stops answering while walking faults the board (third miss); Ctrl-C after that
    // asks a board in Fault to stop, which it refuses: that is nothing to stop, not an error that
    // would end the command without its recording.
    let gait = SyntheticGait::new(40, 0.6).build();
    let mut b = walking(&gait, Duration::from_secs(2));
    let id = GaitTable::parse(&gait).unwrap().joint(0).unwrap().servo_id;
    b.transport()
        .robot()
        .with_chain(|c| {
            c.set_faults(
                id,
                dynamixel::sim::Faults {
                    no_reply: true,
                    ..Default::default()
                },
            )
        })
        .unwrap();
    b.wait(Duration::from_millis(200)).unwrap();
    let st = b.status().unwrap();
    assert_eq!(st.state, RunState::Fault, "{st:?}");
    assert!(st.fault.is_some());
    assert_eq!(stop_walk(&mut b).unwrap(), Stopped::NotWalking);
}

use crate::gate;

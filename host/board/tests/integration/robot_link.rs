//! The typed board client against the in-process virtual robot: connect, upload with verification,
//! list, play, telemetry, stop, emergency stop, and the failures (interrupted upload, board gone).

use std::time::Duration;

use board::link::{Board, LinkError};
use board::robot::{VirtualRobot, VirtualTransport};
use firmware::testkit::SyntheticGait;
use protocol::{Direction, PlayCommand, RunState, Steps};

fn board() -> Board<VirtualTransport> {
    Board::connect(VirtualTransport::new(VirtualRobot::new())).unwrap()
}

fn play(slot: u8, steps: u32, direction: Direction) -> PlayCommand {
    PlayCommand {
        slot,
        direction,
        period_scale: 1000,
        steps: Steps::Count(steps),
    }
}

#[test]
fn connect_reports_the_versions_of_this_host() {
    let b = board();
    assert_eq!(b.info().protocol_version, protocol::PROTOCOL_VERSION);
    assert_eq!(
        b.info().table_format_version,
        protocol::gait::FORMAT_VERSION
    );
    assert_eq!(b.info().slots.len(), 4);
}

#[test]
fn upload_verifies_and_reports_what_it_replaced() {
    let mut b = board();
    let first = SyntheticGait::new(100, 1.0).build();
    let r = gate::upload(&mut b, 1, &first).unwrap();
    assert_eq!(r.replaced, None);
    assert_eq!(r.bytes as usize, first.len());
    // 22 joints x 100 slices = 9 188 bytes in chunks of at most 512: 18 chunks.
    assert_eq!(first.len(), 36 + 22 * 16 + 100 * (2 + 22 * 4) + 4);
    assert_eq!(r.chunks as usize, first.len().div_ceil(512));
    let second = SyntheticGait::new(50, 0.5).build();
    let r2 = gate::upload(&mut b, 1, &second).unwrap();
    assert_eq!(r2.replaced, Some(r.stored));
    assert_eq!(r2.stored.header.slice_count, 50);
    let slots = b.gaits().unwrap();
    assert_eq!(slots[1].gait, Some(r2.stored));
    assert!(slots[0].gait.is_none());
}

#[test]
fn a_gait_plays_its_steps_and_the_robot_stands_again() {
    let mut b = board();
    gate::upload(&mut b, 0, &SyntheticGait::new(100, 1.0).build()).unwrap();
    gate::play(&mut b, play(0, 3, Direction::Forward)).unwrap();
    let mut last_step = 0;
    let mut cycles = 0;
    let mut t0 = None;
    while let Some(t) = b.telemetry(Duration::from_secs(1)).unwrap() {
        t0.get_or_insert(t.time_us);
        last_step = t.step;
        cycles += 1;
        if t.time_us - t0.unwrap() > 10_000_000 {
            break;
        }
        if b.status().unwrap().state == RunState::Standing && t.step == 3 {
            break;
        }
    }
    assert_eq!(last_step, 3);
    // Three 1 s steps at 100 Hz, plus the start ramp (at least 0.5 s).
    assert!(cycles >= 350, "{cycles} cycles");
    assert_eq!(b.status().unwrap().state, RunState::Standing);
}

#[test]
fn an_upload_cut_midway_leaves_the_old_gait() {
    let old = SyntheticGait::new(100, 1.0).build();
    let mut b = board();
    let before = gate::upload(&mut b, 2, &old).unwrap().stored;
    let mut t = b.into_transport();
    t.cut_after_sent(3000);
    let mut b = Board::connect(t).unwrap();
    let new = SyntheticGait::new(80, 0.8).build();
    let err = gate::upload(&mut b, 2, &new).unwrap_err();
    assert!(matches!(err, LinkError::Vanished { .. }), "{err}");
    // Power cycle the robot: the store mounts from flash alone.
    let flash = b.into_transport().into_robot().into_flash();
    let mut b = Board::connect(VirtualTransport::new(VirtualRobot::with_flash(flash))).unwrap();
    assert_eq!(b.gaits().unwrap()[2].gait, Some(before));
}

/// Plays `steps` steps of the synthetic 1 s gait and returns the board once it is walking.
fn walking(steps: Steps) -> Board<VirtualTransport> {
    let mut b = board();
    gate::upload(&mut b, 0, &SyntheticGait::new(100, 1.0).build()).unwrap();
    gate::play(&mut b, PlayCommand::forward(0, steps)).unwrap();
    while b.status().unwrap().state != RunState::Walking {
        b.wait(Duration::from_millis(50)).unwrap();
    }
    b
}

#[test]
fn stop_ends_the_walk_at_the_end_of_the_step() {
    let mut b = walking(Steps::Continuous);
    b.wait(Duration::from_millis(1300)).unwrap();
    b.discard_telemetry();
    b.stop().unwrap();
    let stopped_at = b.now();
    let mut last = None;
    while b.status().unwrap().state != RunState::Standing {
        b.wait(Duration::from_millis(10)).unwrap();
        assert!(
            b.now() - stopped_at < Duration::from_secs(2),
            "still walking"
        );
    }
    while let Some(t) = b.telemetry(Duration::ZERO).unwrap() {
        last = Some(t);
    }
    let last = last.unwrap();
    // Standing comes at a step boundary: the last walking record is at the end of a step
    // (slice 99 of 100, or 0 of the next) and within one step of the stop.
    assert!(
        last.slice >= 98 || last.slice <= 1,
        "stopped at slice {}",
        last.slice
    );
    assert!(b.now() - stopped_at <= Duration::from_millis(1100));
}

#[test]
fn estop_drops_torque_on_every_servo_at_once() {
    let mut b = walking(Steps::Continuous);
    b.wait(Duration::from_millis(300)).unwrap();
    b.emergency_stop().unwrap();
    b.wait(Duration::from_millis(50)).unwrap();
    let st = b.status().unwrap();
    assert_eq!(st.state, RunState::Fault);
    assert_eq!(st.fault.unwrap().kind, protocol::FaultKind::EmergencyStop);
    assert_eq!(st.torque_enabled, 0);
    let robot = b.transport().robot();
    robot.with_chain(|c| {
        assert_eq!(c.servos().len(), 22);
        for s in c.servos() {
            assert!(!s.torque_enabled(), "servo {}", s.id());
        }
    });
    // Play is refused until the fault is cleared.
    let e = gate::play(&mut b, play(0, 1, Direction::Forward)).unwrap_err();
    assert!(e.to_string().contains("Play refused"), "{e}");
    // Naming the fault, not only the state (issue #30 item 8).
    assert!(
        e.to_string()
            .contains("in a fault (EmergencyStop: emergency stop by the host)"),
        "{e}"
    );
    b.clear_fault().unwrap();
    assert_eq!(b.status().unwrap().state, RunState::Idle);
}

#[test]
fn torque_on_right_after_an_upload_waits_for_the_board_to_find_its_servos() {
    // The upload brings a joint map, so the board boots again (RunState::Boot) and refuses
    // SetTorque until it has found the 22 servos: the host waits that out instead of failing
    // with "not allowed in state ...".
    let mut b = board();
    gate::upload(&mut b, 0, &SyntheticGait::new(100, 1.0).build()).unwrap();
    assert_eq!(b.status().unwrap().state, RunState::Boot);
    b.set_torque(protocol::ServoSelect::All, true).unwrap();
    assert_eq!(b.status().unwrap().state, RunState::Standing);
    b.wait(Duration::from_millis(50)).unwrap();
    b.transport().robot().with_chain(|c| {
        assert_eq!(c.servos().len(), 22);
        assert!(c.servos().iter().all(|s| s.torque_enabled()));
    });
}

/// A board that answers every request with `answer(seq)` (or never, with `None`), on a clock that
/// moves by the timeout each time the client waits in vain.
#[derive(Debug)]
struct Scripted {
    answer: fn(u16) -> Option<protocol::DeviceMessage>,
    acc: protocol::FrameAccumulator,
    out: Vec<u8>,
    now: Duration,
}

impl board::link::Transport for Scripted {
    fn send(&mut self, bytes: &[u8]) -> Result<(), board::link::TransportError> {
        for m in self.acc.messages::<protocol::HostMessage>(bytes) {
            if let Ok(protocol::HostMessage::Request { seq, .. }) = m
                && let Some(reply) = (self.answer)(seq)
            {
                self.out
                    .extend(protocol::frame::encode_frame_vec(&reply).unwrap());
            }
        }
        Ok(())
    }
    fn recv(
        &mut self,
        buf: &mut [u8],
        timeout: Duration,
    ) -> Result<usize, board::link::TransportError> {
        if self.out.is_empty() {
            self.now += timeout;
            return Ok(0);
        }
        let n = buf.len().min(self.out.len());
        buf[..n].copy_from_slice(&self.out[..n]);
        self.out.drain(..n);
        Ok(n)
    }
    fn name(&self) -> &str {
        "scripted"
    }
    fn now(&self) -> Duration {
        self.now
    }
}

fn scripted(answer: fn(u16) -> Option<protocol::DeviceMessage>) -> Scripted {
    Scripted {
        answer,
        acc: protocol::FrameAccumulator::new(),
        out: Vec::new(),
        now: Duration::ZERO,
    }
}

fn info(protocol_version: u16) -> protocol::DeviceInfo {
    protocol::DeviceInfo {
        firmware: protocol::FirmwareVersion {
            major: 9,
            minor: 0,
            patch: 0,
        },
        protocol_version,
        table_format_version: protocol::gait::FORMAT_VERSION,
        build_id: 0,
        capabilities: protocol::Capabilities::empty(),
        slot_capacity: 0,
        max_chunk_len: 512,
        slots: heapless::Vec::new(),
    }
}

#[test]
fn a_board_of_another_protocol_version_is_refused_by_name() {
    let t = scripted(|seq| {
        Some(protocol::DeviceMessage::Reply {
            seq,
            response: protocol::Response::DeviceInfo(info(protocol::PROTOCOL_VERSION + 1)),
        })
    });
    let e = Board::connect(t).unwrap_err();
    assert!(matches!(e, LinkError::ProtocolVersion { .. }), "{e}");
    let text = e.to_string();
    assert!(
        text.contains("scripted") && text.contains("update dbot"),
        "{text}"
    );
}

#[test]
fn silence_is_no_reply_after_the_timeout() {
    let e = Board::connect(scripted(|_| None)).unwrap_err();
    let LinkError::NoReply {
        request,
        timeout_ms,
        ..
    } = &e
    else {
        panic!("{e}");
    };
    assert_eq!(*request, "GetDeviceInfo");
    assert_eq!(
        *timeout_ms,
        board::link::DEFAULT_REPLY_TIMEOUT.as_millis() as u64
    );
}

#[test]
fn a_reply_to_another_request_is_not_taken_for_ours() {
    // Answers with the wrong sequence number: the client must keep waiting, then time out.
    let t = scripted(|seq| {
        Some(protocol::DeviceMessage::Reply {
            seq: seq.wrapping_add(7),
            response: protocol::Response::DeviceInfo(info(protocol::PROTOCOL_VERSION)),
        })
    });
    assert!(matches!(
        Board::connect(t).unwrap_err(),
        LinkError::NoReply { .. }
    ));
}

use crate::gate;

/// A wait whose deadline falls between two of the robot's microsecond ticks (1/120 s is
/// 8333.33 us) returns: the virtual link rounds what is left up to the next tick. Before the
/// fix a timeout under 1 us left the clock where it was and `wait` looped forever (seen at
/// 120 and 140 Hz in `python/tests/test_latency.py`).
#[test]
fn a_wait_to_a_deadline_between_two_microseconds_returns_at_the_next_one() {
    use board::link::Transport;
    let mut t = VirtualTransport::new(VirtualRobot::new());
    let mut buf = [0u8; 64];
    // What the board says at boot, first; then it has nothing to say: time passes to the deadline.
    while t.recv(&mut buf, Duration::from_millis(1)).unwrap() > 0 {}
    let t0 = t.now();
    assert_eq!(t.recv(&mut buf, Duration::from_nanos(300)).unwrap(), 0);
    assert_eq!(t.now() - t0, Duration::from_micros(1));
    // Through the board client: 10 waits of 1/120 s end at ceil(10 x 8333.33 us) or below
    // (each wait rounds up its own remainder, never by more than 1 us).
    let mut b = Board::connect(VirtualTransport::new(VirtualRobot::new())).unwrap();
    let start = b.transport().now();
    for _ in 0..10 {
        b.wait(Duration::from_secs_f64(1.0 / 120.0)).unwrap();
    }
    let waited = (b.transport().now() - start).as_micros();
    assert!((83_334..=83_340).contains(&waited), "{waited} us");
}

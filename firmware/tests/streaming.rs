//! Streaming proprioception against the simulated wire: setpoints arrive at every phase of the bus
//! cycle (also while its transaction is on the wire), the link converts records several cycles late,
//! and every record must name what its own cycle's Sync Write carried and what its Sync Read
//! returned. The truth is the wire itself, tapped and decoded with the Dynamixel packet parser.

use core::cell::RefCell;
use core::future::{Future, poll_fn};
use core::pin::pin;
use core::task::Poll;
use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::rc::Rc;

use dynamixel::control_table::{FEEDBACK_ADDR, GOAL_POSITION, PRESENT_POSITION};
use dynamixel::instruction::{Instruction, STATUS};
use dynamixel::master::Clock;
use dynamixel::parser::Parser;
use dynamixel::sim::{SimIoError, SimWire};
use firmware::board::Board;
use firmware::controller::Config;
use firmware::safety::State;
use firmware::store::nor_double::NorDouble;
use firmware::testkit::rig::{
    SECTORS, SimBoardOn, ask, board_on, play, run_until, status, upload, wire,
};
use firmware::testkit::{JOINTS, SyntheticGait};
use protocol::{
    Client, DeviceMessage, FrameAccumulator, JointSetpoint, MAX_FRAME_LEN, Proprioception, Request,
    Response, Setpoint, StreamConfig,
};

/// The bus side of the simulated wire with a copy of every byte the master sends and hears.
#[derive(Debug, Clone)]
struct Tap {
    wire: SimWire,
    sent: Rc<RefCell<Vec<u8>>>,
    heard: Rc<RefCell<Vec<u8>>>,
}

impl embedded_io_async::ErrorType for Tap {
    type Error = SimIoError;
}

impl embedded_io_async::Read for Tap {
    async fn read(&mut self, buf: &mut [u8]) -> Result<usize, SimIoError> {
        let n = self.wire.read(buf).await?;
        self.heard.borrow_mut().extend_from_slice(&buf[..n]);
        Ok(n)
    }
}

impl embedded_io_async::ReadReady for Tap {
    fn read_ready(&mut self) -> Result<bool, SimIoError> {
        self.wire.read_ready()
    }
}

impl embedded_io_async::Write for Tap {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, SimIoError> {
        let n = self.wire.write(buf).await?;
        self.sent.borrow_mut().extend_from_slice(&buf[..n]);
        Ok(n)
    }

    async fn flush(&mut self) -> Result<(), SimIoError> {
        self.wire.flush().await
    }
}

/// What one cycle put on the wire: the goals of its Sync Write (if any) and the present positions
/// in its status packets, by servo ID.
#[derive(Debug, Default)]
struct Traffic {
    goals: Option<BTreeMap<u8, i32>>,
    present: BTreeMap<u8, i32>,
}

/// Every packet in `bytes` (instruction and status), in order; a bad one fails the test.
fn packets(bytes: &[u8], mut each: impl FnMut(u8, u8, &[u8])) {
    let mut p = Parser::<256>::new();
    let mut rest = bytes;
    loop {
        let took = p.feed(rest);
        rest = &rest[took..];
        while let Some(f) = p.next_frame() {
            let f = f.expect("every packet on the simulated wire is intact");
            each(f.id, f.instruction, f.params);
        }
        if rest.is_empty() {
            return;
        }
    }
}

/// Decodes the tapped bytes of one cycle and clears the tap.
fn take_traffic(tap: &Tap) -> Traffic {
    let mut t = Traffic::default();
    packets(&tap.sent.borrow_mut().split_off(0), |_, inst, params| {
        let addr = u16::from_le_bytes([params[0], params[1]]);
        // The Sync Write of Goal Position (not the one of Torque Enable).
        if inst == Instruction::SyncWrite as u8 && addr == GOAL_POSITION.addr {
            let len = usize::from(u16::from_le_bytes([params[2], params[3]]));
            assert_eq!(len, 4);
            let goals = params[4..]
                .chunks(1 + len)
                .map(|c| (c[0], i32::from_le_bytes([c[1], c[2], c[3], c[4]])))
                .collect();
            t.goals = Some(goals);
        }
    });
    // Status packets: ERR, then the data from register 126 on.
    let at = 1 + usize::from(PRESENT_POSITION.addr - FEEDBACK_ADDR);
    packets(&tap.heard.borrow_mut().split_off(0), |id, inst, params| {
        // (A heat and supply read's status, 3 data bytes, is not feedback.)
        if inst == STATUS && params.len() >= at + 4 {
            let b = &params[at..at + 4];
            t.present
                .insert(id, i32::from_le_bytes([b[0], b[1], b[2], b[3]]));
        }
    });
    t
}

type TapBoard = SimBoardOn<Tap>;

/// 22 virtual servos on a tapped wire at `baud`, Return Delay Time 0.
fn rig(baud: u32, cycle_hz: u16) -> (TapBoard, SimWire, Tap) {
    let wire = wire(baud);
    let tap = Tap {
        wire: wire.clone(),
        sent: Rc::default(),
        heard: Rc::default(),
    };
    let config = Config {
        cycle_hz,
        baud,
        ..Config::default()
    };
    let board = board_on(NorDouble::new(SECTORS), config, tap.clone(), &wire);
    (board, wire, tap)
}

/// Setpoint `seq`: every joint at its own angle, 0.01 rad (6.5 ticks) apart from seq to seq, so
/// that the goals on the wire name the setpoint they came from.
fn angle(seq: u32, joint: usize) -> i16 {
    (-3000 + 100 * seq as i32 + 37 * joint as i32) as i16
}

fn setpoint_frame(seq: u32) -> Vec<u8> {
    let sp = Setpoint {
        seq,
        joints: (0..JOINTS)
            .map(|j| JointSetpoint {
                angle: angle(seq, j),
                torque: None,
            })
            .collect(),
    };
    let mut buf = [0u8; MAX_FRAME_LEN];
    Client::encode_setpoint(&sp, &mut buf).unwrap().to_vec()
}

/// Joint angle (1e-4 rad) of a servo position, from the synthetic gait's zero and sign:
/// (ticks - zero) x sign x 2 pi / 4096.
fn ticks_to_angle(gait: &SyntheticGait, joint: usize, ticks: i32) -> f64 {
    let spec = &gait.joints[joint];
    let sign = match spec.sign {
        protocol::gait::Sign::Positive => 1.0,
        protocol::gait::Sign::Negative => -1.0,
    };
    f64::from(ticks - i32::from(spec.zero_offset)) * sign * 2.0 * PI / 4096.0 * 1e4
}

/// The setpoint whose goals a Sync Write carried (each goal within a tick of the angle's), if any.
fn carried(gait: &SyntheticGait, goals: &BTreeMap<u8, i32>, sent: u32) -> Option<u32> {
    (1..=sent).find(|&seq| {
        (0..JOINTS).all(|j| {
            let a = ticks_to_angle(gait, j, goals[&(j as u8 + 1)]);
            (a - f64::from(angle(seq, j))).abs() <= 2.0 * PI / 4096.0 * 1e4
        })
    })
}

/// Runs the next bus cycle while the link task takes `frame` at `at_us` (simulated time), which
/// may fall before the cycle's plan, inside its bus transaction or after it.
fn cycle_with_setpoint(board: &mut TapBoard, wire: &SimWire, frame: &[u8], at_us: u64) {
    let Board {
        controller,
        bus,
        schedule,
        link,
    } = board;
    let controller = &*controller;
    let mut cycle = pin!(schedule.run_cycle(controller, bus));
    let mut inject = pin!(async {
        wire.wait_until(at_us).await;
        let mut answers = 0;
        link.receive(controller, frame, &mut |_| answers += 1);
        assert_eq!(answers, 0, "the setpoint was rejected");
    });
    let (mut cycled, mut injected) = (false, false);
    wire.block_on(poll_fn(|cx| {
        cycled = cycled || cycle.as_mut().poll(cx).is_ready();
        injected = injected || inject.as_mut().poll(cx).is_ready();
        if cycled && injected {
            Poll::Ready(())
        } else {
            Poll::Pending
        }
    }));
}

/// The proprioception records the link has queued, converted now.
fn drain(board: &mut TapBoard) -> Vec<Proprioception> {
    let mut acc = FrameAccumulator::new();
    let mut out = Vec::new();
    board.drain_telemetry(|f| {
        for &b in f {
            match acc.push_message::<DeviceMessage>(b) {
                Some(Ok(DeviceMessage::Proprioception(p))) => out.push(p),
                Some(m) => panic!("streaming sent {m:?}"),
                None => {}
            }
        }
    });
    out
}

/// Standing after one played step, telemetry off, then streaming with feedback every cycle.
fn standing_then_streaming(baud: u32, cycle_hz: u16) -> (TapBoard, SimWire, Tap, SyntheticGait) {
    let (mut board, wire, tap) = rig(baud, cycle_hz);
    let mut client = Client::new();
    let gait = SyntheticGait::new(100, 1.0);
    run_until(&mut board, &wire, 5, |s| s == State::Idle);
    upload(&mut board, &mut client, 0, &gait.build());
    // Boot again with the upload's joint map: all 22 found.
    run_until(&mut board, &wire, 5, |s| s == State::Idle);
    play(&mut board, &mut client, protocol::Steps::Count(1));
    run_until(&mut board, &wire, 2000, |s| s == State::Standing);
    let off = ask(&mut board, &mut client, Request::SetTelemetry { every: 0 });
    assert_eq!(off, Response::Ack);
    let enter = Request::EnterStreaming(StreamConfig {
        timeout_cycles: 1000,
        feedback_every: 1,
    });
    assert_eq!(ask(&mut board, &mut client, enter), Response::Ack);
    // The board moves each goal toward a setpoint by at most the servo's step per cycle
    // (firmware::goal_step: 18 ticks on an MX-28 at 200 Hz), and the standing posture is up to
    // 0.7 rad (456 ticks) from setpoint 0's: settle there first, so that the consecutive
    // setpoints of the tests, 0.01 rad (6.5 ticks) apart, each reach the wire in one cycle.
    board.receive(&setpoint_frame(0), |_| panic!("setpoint 0 rejected"));
    for _ in 0..40 {
        wire.block_on(board.run_cycle());
    }
    let settled = take_traffic(&tap);
    let goals = settled.goals.expect("a streaming cycle writes goals");
    for j in 0..JOINTS {
        let a = ticks_to_angle(&gait, j, goals[&(j as u8 + 1)]);
        assert!(
            (a - f64::from(angle(0, j))).abs() <= 2.0 * PI / 4096.0 * 1e4,
            "joint {j} did not reach setpoint 0: {a:.1}"
        );
    }
    board.drain_telemetry(|_| {});
    (board, wire, tap, gait)
}

/// Setpoint `seq` with every joint 1 rad (10 000 x 1e-4 rad) past its angle of setpoint 0.
fn one_rad_on_frame(seq: u32) -> Vec<u8> {
    let sp = Setpoint {
        seq,
        joints: (0..JOINTS)
            .map(|j| JointSetpoint {
                angle: angle(0, j) + 10_000,
                torque: None,
            })
            .collect(),
    };
    let mut buf = [0u8; MAX_FRAME_LEN];
    Client::encode_setpoint(&sp, &mut buf).unwrap().to_vec()
}

#[test]
fn a_setpoint_1_rad_away_is_approached_at_the_servos_speed_never_jumped_to() {
    let (mut board, wire, tap, gait) = standing_then_streaming(1_000_000, 100);
    let limited_before = board.controller.borrow().counters().rate_limited;
    board.receive(&one_rad_on_frame(1), |_| panic!("setpoint rejected"));
    // Per cycle at 100 Hz, by hand: no-load speed x 10 ms in ticks (4096 per turn), rounded
    // down. MX-28: 55 rev/min x 4096 / 60 / 100 = 37.55 -> 37; MX-64: 63 x 4096 / 6000 = 43.01
    // -> 43. 1 rad is 4096 / 2 pi = 651.9 ticks, so each goal is 651 or 652 ticks away (the two
    // postures round separately): ceil(651.9 / 37) = 18 cycles on an MX-28 (17 x 37 = 629 falls
    // short), ceil(651.9 / 43) = 16 on an MX-64 (15 x 43 = 645 falls short).
    let step = |j: usize| match gait.joints[j].model {
        protocol::ServoModel::Mx28 => (37, 18),
        protocol::ServoModel::Mx64 => (43, 16),
    };
    let mut last: Vec<i32> = board.controller.borrow().goals().to_vec();
    let mut arrived = [None; JOINTS];
    for cycle in 1..=25 {
        wire.block_on(board.run_cycle());
        let goals = take_traffic(&tap)
            .goals
            .expect("a streaming cycle writes goals");
        for j in 0..JOINTS {
            let g = goals[&(j as u8 + 1)];
            let moved = (g - last[j]).abs();
            let (max, _) = step(j);
            assert!(
                moved <= max,
                "cycle {cycle} joint {j}: moved {moved} > {max}"
            );
            if arrived[j].is_none() {
                let a = ticks_to_angle(&gait, j, g);
                if (a - f64::from(angle(0, j) + 10_000)).abs() <= 2.0 * PI / 4096.0 * 1e4 {
                    arrived[j] = Some(cycle);
                } else {
                    // On the way, every cycle takes the whole step.
                    assert_eq!(moved, max, "cycle {cycle} joint {j}");
                }
            }
            last[j] = g;
        }
        // Keep the stream alive.
        board.receive(&one_rad_on_frame(cycle + 1), |_| {
            panic!("setpoint rejected")
        });
    }
    for (j, a) in arrived.iter().enumerate() {
        assert_eq!(*a, Some(step(j).1), "joint {j} arrival cycle");
    }
    let limited = board.controller.borrow().counters().rate_limited - limited_before;
    // 17 cut cycles on each MX-28 and 15 on each MX-64.
    let mx64 = (0..JOINTS).filter(|&j| step(j).0 == 43).count() as u32;
    assert_eq!(limited, 17 * (JOINTS as u32 - mx64) + 15 * mx64);
    // The host sees the same count in the board's status.
    let s = status(&mut board, &mut Client::new());
    assert_eq!(s.counters.rate_limited - limited_before, limited);
}

/// Streams for `n` cycles, a setpoint in six of every seven at a phase spread over the period
/// (inside the bus transaction too); converts records only every 5th cycle. Checks every record
/// against the wire.
fn every_record_names_its_own_cycle(baud: u32, cycle_hz: u16, n: u32) {
    let (mut board, wire, tap, gait) = standing_then_streaming(baud, cycle_hz);
    let period = u64::from(board.controller.borrow().period_us());
    // Wire traffic by cycle number (the records' `cycle`).
    let mut traffic = BTreeMap::new();
    let mut records = Vec::new();
    let mut next_start = wire.now_us();
    let overruns = board.timing().overruns;
    let dropped = board.controller.borrow().telemetry_dropped();
    let (mut sent, mut during_transaction, mut max_lag) = (0, 0, 0);
    for k in 0..n {
        if k % 7 == 6 {
            // No setpoint: the last one is held a second cycle.
            wire.block_on(board.run_cycle());
        } else {
            sent += 1;
            // 37 and 100 are coprime: the arrivals visit every hundredth of the period.
            let at = next_start + period * u64::from(k * 37 % 100) / 100;
            cycle_with_setpoint(&mut board, &wire, &setpoint_frame(sent), at);
            if at < board.timing().last_start_us + u64::from(board.timing().max_busy_us) {
                during_transaction += 1;
            }
        }
        next_start = board.timing().last_start_us + period;
        let cycle = board.controller.borrow().counters().cycles;
        traffic.insert(cycle, take_traffic(&tap));
        if k % 5 == 4 {
            let batch = drain(&mut board);
            max_lag = max_lag.max(batch.iter().map(|r| cycle - r.cycle).max().unwrap_or(0));
            records.extend(batch);
        }
    }
    records.extend(drain(&mut board));
    let c = board.controller.borrow();
    assert_eq!(c.state(), State::Streaming);
    assert_eq!(c.telemetry_dropped(), dropped, "records dropped");
    drop(c);
    assert_eq!(
        board.timing().overruns,
        overruns,
        "the injections delayed the bus loop"
    );
    eprintln!(
        "{cycle_hz} Hz: {} records, {during_transaction} setpoints arrived during a bus \
         transaction, records converted up to {max_lag} cycles late",
        records.len()
    );
    // The race is exercised: setpoints arrive while a cycle's transaction is on the wire, and
    // the link converts records cycles after they were taken.
    assert!(during_transaction >= 10, "{during_transaction}");
    assert!(max_lag >= 4, "{max_lag}");

    // One record per cycle though telemetry is off (feedback_every = 1).
    let cycles: Vec<u32> = records.iter().map(|r| r.cycle).collect();
    assert_eq!(cycles, traffic.keys().copied().collect::<Vec<_>>());

    let mut run: Option<(u32, u16)> = None;
    let mut held = 0;
    for r in &records {
        let t = &traffic[&r.cycle];
        let goals = t.goals.as_ref().expect("a streaming cycle writes goals");
        let on_wire = carried(&gait, goals, sent).unwrap_or(0);
        assert_eq!(
            r.setpoint_seq, on_wire,
            "cycle {}: the record names setpoint {}, its Sync Write carried {on_wire}",
            r.cycle, r.setpoint_seq
        );
        // Age: cycles this setpoint has been on the wire, this one included.
        let age = match run {
            Some((s, a)) if s == on_wire => a + 1,
            _ => 1,
        };
        run = Some((on_wire, age));
        assert_eq!(r.setpoint_age, age, "cycle {} age", r.cycle);
        if on_wire != 0 && age > 1 {
            held += 1;
        }
        for (j, fb) in r.joints.iter().enumerate() {
            let id = j as u8 + 1;
            let commanded = ticks_to_angle(&gait, j, goals[&id]);
            assert!(
                (f64::from(fb.commanded) - commanded).abs() <= 1.0,
                "cycle {} joint {j}: commanded {} in the record, {commanded:.1} on the wire",
                r.cycle,
                fb.commanded
            );
            let present = ticks_to_angle(&gait, j, t.present[&id]);
            assert!(
                (f64::from(fb.present) - present).abs() <= 1.0,
                "cycle {} joint {j}: present {} in the record, {present:.1} in the reply",
                r.cycle,
                fb.present
            );
        }
    }
    assert!(held >= n / 7 - 1, "held setpoints: {held}");
}

#[test]
fn proprioception_names_the_setpoint_its_sync_write_carried_at_100_hz() {
    every_record_names_its_own_cycle(1_000_000, 100, 100);
}

#[test]
fn proprioception_names_the_setpoint_its_sync_write_carried_at_200_hz() {
    // 1 Mbit/s cannot carry 200 cycles per second (6.2 ms of wire); 4 Mbit/s can.
    every_record_names_its_own_cycle(4_000_000, 200, 100);
}

#[test]
fn feedback_every_governs_streaming_and_telemetry_every_playback() {
    let (mut board, wire, _tap, _) = standing_then_streaming(1_000_000, 100);
    let mut client = Client::new();
    // A first session that takes setpoint 40.
    board.receive(&setpoint_frame(40), |_| panic!("setpoint 40 rejected"));
    wire.block_on(board.run_cycle());
    assert_eq!(drain(&mut board)[0].setpoint_seq, 40);
    // Telemetry every cycle does not make streaming send more than feedback_every asks for.
    assert_eq!(
        ask(&mut board, &mut client, Request::SetTelemetry { every: 1 }),
        Response::Ack
    );
    assert_eq!(
        ask(&mut board, &mut client, Request::LeaveStreaming),
        Response::Ack
    );
    let enter = Request::EnterStreaming(StreamConfig {
        timeout_cycles: 1000,
        feedback_every: 3,
    });
    assert_eq!(ask(&mut board, &mut client, enter), Response::Ack);
    let first = board.controller.borrow().counters().cycles + 1;
    let mut records = Vec::new();
    for k in 0..30 {
        if k % 10 == 0 {
            records.extend(drain(&mut board));
        }
        wire.block_on(board.run_cycle());
        board.receive(&setpoint_frame(k + 1), |_| {
            panic!("setpoint {} rejected", k + 1)
        });
    }
    records.extend(drain(&mut board));
    let cycles: Vec<u32> = records.iter().map(|r| r.cycle).collect();
    let want: Vec<u32> = (0..10).map(|i| first + 3 * i).collect();
    assert_eq!(cycles, want);
    // The new session's first cycle ran before its first setpoint: it names none (0), not the
    // earlier session's 40. Then every third cycle, each naming the setpoint sent after the
    // cycle before it: 3, 6, ...
    let seqs: Vec<u32> = records.iter().map(|r| r.setpoint_seq).collect();
    let want: Vec<u32> = (0..10).map(|i| 3 * i).collect();
    assert_eq!(seqs, want);
}

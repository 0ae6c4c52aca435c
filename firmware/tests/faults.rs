//! Fault campaign on the whole firmware library (link, controller, bus loop, bus master, gait store)
//! against the dynamixel crate's virtual servo chain on its simulated half-duplex wire and the NOR
//! flash double: one test per fault of docs/reliability.md, each checking the behaviour written
//! there. Faults already covered elsewhere (overload: `walk_on_the_wire`; power loss at every flash tick:
//! `store::tests`) are referenced in that table, not repeated here.

use dynamixel::sim::{Faults, SimWire};
use firmware::controller::Config;
use firmware::safety::{SafeReason, State};
use firmware::store::nor_double::NorDouble;
use firmware::testkit::rig::{
    self, JointTrace, SECTORS, SimBoard, ask, board_on, cycle, exchange, play, rig, run_until,
    slots, state, status, telemetry, upload, upload_requests, wire,
};
use firmware::testkit::{JOINTS, SyntheticGait};
use protocol::{
    Client, DeviceMessage, FaultKind, ProtocolError, Request, Response, RunState, Telemetry,
};

/// A rig walking continuously with the synthetic gait in slot 0 (100 slices, 1 s per step).
fn walking() -> (SimBoard, SimWire, Client, Vec<u8>) {
    let table = SyntheticGait::new(100, 1.0).build();
    let (board, wire, client) = rig::walking(1_000_000, 100, &table);
    (board, wire, client, table)
}

/// The CRC a table carries in its last four bytes (what ListGaits reports), computed here.
fn table_crc(table: &[u8]) -> u32 {
    protocol::crc32::checksum(&table[..table.len() - 4])
}

fn set_faults(wire: &SimWire, id: u8, faults: Faults) {
    wire.with_chain(|c| c.set_faults(id, faults)).unwrap();
}

/// After a servo fault: `Play` is refused; servo `id` is healed, the fault cleared, and the robot
/// comes up Idle and walks again.
fn refused_until_cleared_then_walks(
    board: &mut SimBoard,
    wire: &SimWire,
    client: &mut Client,
    id: u8,
) {
    let r = ask(
        board,
        client,
        Request::Play(protocol::PlayCommand {
            slot: 0,
            direction: protocol::Direction::Forward,
            period_scale: 1000,
            steps: protocol::Steps::Count(1),
        }),
    );
    assert!(
        matches!(r, Response::Error(ProtocolError::WrongState { .. })),
        "{r:?}"
    );
    set_faults(wire, id, Faults::default());
    assert_eq!(ask(board, client, Request::ClearFault), Response::Ack);
    run_until(board, wire, 10, |s| s == State::Idle);
    play(board, client, protocol::Steps::Count(1));
    run_until(board, wire, 500, |s| s == State::Walking);
}

#[test]
fn a_silent_servo_stops_the_walk_after_the_miss_limit_naming_its_joint() {
    let (mut board, wire, mut client, _) = walking();
    let before = board.controller.borrow().counters().timeouts;
    // Servo 7 (joint 6) executes goals but stops answering.
    set_faults(&wire, 7, Faults::SILENT);
    let limit = Config::default().miss_limit;
    // Walking goes on through limit - 1 missed cycles, and stops at the limit-th.
    for _ in 0..limit - 1 {
        cycle(&mut board, &wire);
        assert_eq!(state(&board), State::Walking);
    }
    cycle(&mut board, &wire);
    assert_eq!(
        state(&board),
        State::Safe(SafeReason::ServoMissing {
            joint: 6,
            id: 7,
            cycles: limit
        })
    );
    let s = status(&mut board, &mut client);
    assert_eq!(s.state, RunState::Fault);
    let fault = s.fault.unwrap();
    assert_eq!(
        (fault.kind, fault.joint),
        (FaultKind::ServoMissing { cycles: limit }, Some(6))
    );
    // Every missed reply was counted.
    assert!(s.counters.bus_timeouts >= before + u32::from(limit));
    // Play is refused until the fault is cleared; the servo answers again, clear, play.
    refused_until_cleared_then_walks(&mut board, &wire, &mut client, 7);
}

#[test]
fn corrupt_replies_are_counted_and_only_a_run_of_them_is_a_fault() {
    let (mut board, wire, mut client, _) = walking();
    let limit = Config::default().miss_limit;
    let corrupt = Faults::BAD_CRC;
    let crc0 = status(&mut board, &mut client).counters.crc_errors;
    // The next limit - 1 replies of servo 12 corrupt, then good ones: a glitch, not a fault.
    // (Counted by replies, not cycles: the servo also answers the bus loop's heat and supply
    // read when its turn comes, and a corrupt reply there is lost and counted too.)
    for round in 0..5 {
        set_faults(&wire, 12, Faults::corrupting_next(u32::from(limit - 1)));
        for _ in 0..limit + 2 {
            cycle(&mut board, &wire);
        }
        wire.with_chain(|c| assert_eq!(c.servo(12).unwrap().faults.corrupt_next, 0));
        assert_eq!(state(&board), State::Walking, "round {round}");
    }
    let crc1 = status(&mut board, &mut client).counters.crc_errors;
    assert_eq!(
        crc1 - crc0,
        5 * u32::from(limit - 1),
        "one CRC error per corrupt reply"
    );
    // A servo whose every reply is corrupt is as good as silent.
    set_faults(&wire, 12, corrupt);
    run_until(&mut board, &wire, usize::from(limit) + 1, |s| {
        matches!(s, State::Safe(_))
    });
    assert_eq!(
        state(&board),
        State::Safe(SafeReason::ServoMissing {
            joint: 11,
            id: 12,
            cycles: limit
        })
    );
}

#[test]
fn a_stuck_servo_stops_the_walk_naming_its_joint_and_shows_in_telemetry() {
    // Servo 3 (joint 2) jams mid-walk: it answers, its present position freezes, no error bit.
    // The stuck rule (safety::stuck, 50-sample windows) reports it within two windows; the robot
    // goes Safe as for a silent servo, and the telemetry up to then shows why.
    let (mut board, wire, mut client, _) = walking();
    for _ in 0..50 {
        cycle(&mut board, &wire);
    }
    set_faults(&wire, 3, Faults::JAMMED);
    let window = usize::from(Config::default().stuck.window);
    let mut records = Vec::new();
    let mut cycles = 0;
    while state(&board) == State::Walking {
        records.extend(cycle(&mut board, &wire));
        cycles += 1;
        assert!(cycles < 2 * window, "not reported after {cycles} cycles");
    }
    let State::Safe(SafeReason::ServoStuck {
        joint: 2,
        id: 3,
        goal_range,
        present_range,
    }) = state(&board)
    else {
        panic!("{:?}", state(&board));
    };
    // The window ran wholly after the jam: the output did not move at all.
    assert_eq!(present_range, 0);
    let s = status(&mut board, &mut client);
    assert_eq!(s.state, RunState::Fault);
    let fault = s.fault.unwrap();
    assert_eq!(
        (fault.kind, fault.joint),
        (
            FaultKind::ServoStuck {
                goal_range,
                present_range: 0
            },
            Some(2)
        )
    );
    // The telemetry of the last window: commanded moved by the goal range, present by nothing
    // (telemetry angles are 1e-4 rad: a tick is 15.3 units).
    let last = &records[records.len() - window..];
    let span = |v: Vec<i16>| i32::from(*v.iter().max().unwrap() - *v.iter().min().unwrap());
    let commanded = span(last.iter().map(|t| t.joints[2].commanded).collect());
    let present = span(last.iter().map(|t| t.joints[2].present).collect());
    let tick = 2.0 * core::f64::consts::PI / 4096.0 * 1e4;
    assert!(
        (f64::from(commanded) - f64::from(goal_range) * tick).abs() <= 2.0 * tick,
        "commanded span {commanded} vs goal range {goal_range} ticks"
    );
    assert_eq!(present, 0);
    // A moving neighbour for comparison: it followed.
    assert!(span(last.iter().map(|t| t.joints[3].present).collect()) > 2000);
    // Play is refused until ClearFault; unjammed and cleared, it walks again.
    refused_until_cleared_then_walks(&mut board, &wire, &mut client, 3);
    run_until(&mut board, &wire, 200, |s| s == State::Standing);
}

#[test]
fn a_loaded_ten_step_walk_never_reports_a_stuck_servo() {
    // The case the stuck rule must not mistake for a jam: the goals carry the torque bias and every
    // servo carries the planned torque of the slice being played as its load (as on a robot whose
    // legs meet the planned forces), so the servos sit near the planned angle, off their goals.
    let gait = SyntheticGait::new(100, 1.0);
    let (mut board, wire, _client) =
        rig::playing(1_000_000, 100, &gait.build(), protocol::Steps::Count(10));
    let mut trace = JointTrace::default();
    let mut walked = 0;
    while state(&board) != State::Standing || walked == 0 {
        let slice = board
            .controller
            .borrow()
            .playback()
            .map(|p| usize::from(p.1));
        wire.with_chain(|c| {
            for j in 0..JOINTS {
                let sign = if j % 2 == 0 { 1.0 } else { -1.0 };
                let nm = slice.map_or(0.0, |s| gait.torque(s, j)) * sign;
                c.set_external_torque(j as u8 + 1, -nm).unwrap();
            }
        });
        cycle(&mut board, &wire);
        let st = state(&board);
        assert!(
            !matches!(st, State::Safe(_)),
            "{st:?} after {walked} cycles"
        );
        if st == State::Walking {
            walked += 1;
            trace.record(&board, &wire);
        }
        assert!(walked < 1100, "the walk did not end");
    }
    assert_eq!(board.controller.borrow().playback().unwrap().0, 10);
    // The margin, measured on the servos themselves: over every 50-cycle window in which a goal
    // moved over more than 40 ticks, how little did that servo move?
    let w = usize::from(Config::default().stuck.window);
    let range = |v: &[i32]| v.iter().max().unwrap() - v.iter().min().unwrap();
    let least = (0..JOINTS)
        .flat_map(|j| {
            let (p, g) = (&trace.present[j], &trace.goal[j]);
            (0..p.len() - w)
                .filter(move |&k| range(&g[k..k + w]) > 40)
                .map(move |k| range(&p[k..k + w]))
        })
        .min()
        .unwrap();
    eprintln!(
        "loaded walk: {walked} cycles; least servo motion in a window whose goal moved > 40 ticks: {least} ticks"
    );
    assert!(least > 20, "{least} ticks");
}

/// Marsaglia's 32-bit xorshift from `seed` (non-zero): deterministic noise, so a failure repeats.
fn xorshift32(mut x: u32) -> impl FnMut() -> u32 {
    move || {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        x
    }
}

#[test]
fn bus_noise_bursts_are_survived_and_counted() {
    let (mut board, wire, mut client, _) = walking();
    let c0 = status(&mut board, &mut client).counters;
    // Every 10th cycle, a burst of noise (including false headers and a fake status packet) is on
    // the wire while the replies come in. Deterministic xorshift, so a failure repeats.
    let mut rnd = xorshift32(0x2545_F491);
    for k in 0..1000 {
        if k % 10 == 0 {
            let mut burst: Vec<u8> = (0..rnd() % 40).map(|_| rnd() as u8).collect();
            burst.extend([0xFF, 0xFF, 0xFD, 0x00, 0x05, 0x20]);
            wire.inject_noise(&burst);
        }
        cycle(&mut board, &wire);
        assert_eq!(state(&board), State::Walking, "cycle {k}");
    }
    let c1 = status(&mut board, &mut client).counters;
    // The bus cycles on at 100 Hz: 1000 cycles, none missed.
    assert_eq!(c1.cycles - c0.cycles, 1000);
    assert_eq!(c1.missed_deadlines, c0.missed_deadlines);
    let errors = (c1.crc_errors - c0.crc_errors) + (c1.bus_timeouts - c0.bus_timeouts);
    eprintln!(
        "noise: {} CRC errors, {} timeouts in 1000 cycles with 100 bursts",
        c1.crc_errors - c0.crc_errors,
        c1.bus_timeouts - c0.bus_timeouts
    );
    // At most a few replies per burst are lost (the burst precedes the replies it hits).
    assert!(errors <= 100 * 3, "{errors} lost replies");
}

/// One bus cycle with `noise` put on the wire the moment the request has left, i.e. at the start
/// of the reply window (the servos, at Return Delay Time 0, start answering then too; `SimWire`
/// puts the noise bytes between the reply bytes that arrive at the same time, garbling both).
/// The telemetry of the cycle.
fn cycle_with_reply_noise(board: &mut SimBoard, wire: &SimWire, noise: &[u8]) -> Vec<Telemetry> {
    let sent0 = wire.byte_counts().0;
    let mut due_us = None;
    let mut injected = false;
    {
        let mut run = core::pin::pin!(board.run_cycle());
        wire.block_on(core::future::poll_fn(|cx| {
            let done = run.as_mut().poll(cx).is_ready();
            if !injected {
                // The request is queued in one write; at 1 Mbit/s each byte takes 10 us.
                let sent = wire.byte_counts().0 - sent0;
                if due_us.is_none() && sent > 0 {
                    due_us = Some(wire.now_us() + sent * 10);
                }
                if due_us.is_some_and(|t| wire.now_us() >= t) {
                    wire.inject_noise(noise);
                    injected = true;
                }
            }
            if done {
                core::task::Poll::Ready(())
            } else {
                core::task::Poll::Pending
            }
        }));
    }
    assert!(injected, "the cycle sent no request");
    telemetry(board)
}

#[test]
fn bus_noise_in_the_reply_window_costs_only_the_replies_it_hits() {
    let (mut board, wire, mut client, _) = walking();
    let c0 = status(&mut board, &mut client).counters;
    // Every 10th cycle, 1 to 60 noise bytes (random, ending in a false header) start with the
    // reply window. Deterministic xorshift, so a failure repeats.
    let mut rnd = xorshift32(0x9E37_79B9);
    let (mut hit_total, mut lost_total) = (0usize, 0usize);
    for k in 0..500 {
        let records = if k % 10 == 0 {
            let mut burst: Vec<u8> = (0..1 + rnd() % 54).map(|_| rnd() as u8).collect();
            burst.extend([0xFF, 0xFF, 0xFD, 0x00, 0x05, 0x20]);
            let records = cycle_with_reply_noise(&mut board, &wire, &burst);
            // Noise byte i lands after reply byte i: the replies overlapped are those of the
            // first burst.len() reply bytes, 21 bytes each (10 data bytes, no stuffing here).
            let hit = burst.len().div_ceil(21);
            let t = records.last().expect("telemetry of the cycle");
            let lost = t
                .joints
                .iter()
                .filter(|j| j.flags & protocol::feedback_flags::NO_REPLY != 0)
                .count();
            assert!(lost <= hit, "cycle {k}: {lost} replies lost to {hit} hit");
            hit_total += hit;
            lost_total += lost;
            records
        } else {
            cycle(&mut board, &wire)
        };
        assert!(!records.is_empty(), "cycle {k}: no telemetry");
        assert_eq!(state(&board), State::Walking, "cycle {k}");
    }
    let c1 = status(&mut board, &mut client).counters;
    assert_eq!(c1.cycles - c0.cycles, 500);
    assert_eq!(c1.missed_deadlines, c0.missed_deadlines);
    eprintln!(
        "reply-window noise: 50 bursts hit {hit_total} replies, {lost_total} lost \
         ({} CRC errors, {} timeouts)",
        c1.crc_errors - c0.crc_errors,
        c1.bus_timeouts - c0.bus_timeouts
    );
    // Every burst garbles at least the reply it starts in.
    assert!(lost_total >= 50, "{lost_total} replies lost to 50 bursts");
}

#[test]
fn a_lost_host_link_does_not_stop_the_walk_and_the_link_comes_back() {
    let (mut board, wire, mut client, _) = walking();
    let step0 = board.controller.borrow().playback().unwrap().0;
    // The host vanishes mid-frame for 5 s (500 cycles): nobody reads telemetry.
    let (_, frame) = client.request_frame(&Request::GetStatus).unwrap();
    assert!(exchange(&mut board, &frame[..frame.len() / 2]).is_empty());
    let dropped0 = board.controller.borrow().telemetry_dropped();
    for _ in 0..500 {
        wire.block_on(board.run_cycle());
    }
    assert_eq!(state(&board), State::Walking);
    assert_eq!(board.controller.borrow().playback().unwrap().0 - step0, 5);
    // The queue holds the last records; the rest were dropped and counted.
    let dropped = board.controller.borrow().telemetry_dropped() - dropped0;
    assert_eq!(dropped, 500 - firmware::controller::TELEMETRY_QUEUE as u32);
    // Back: the half frame is rejected as one bad frame, the next request is answered.
    let reconnect = exchange(&mut board, &[0]);
    assert!(
        matches!(reconnect.as_slice(), [DeviceMessage::Rejected(_)]),
        "{reconnect:?}"
    );
    let s = status(&mut board, &mut client);
    assert_eq!(s.state, RunState::Walking);
    assert_eq!(s.counters.telemetry_dropped, dropped + dropped0);
    assert!(
        !cycle(&mut board, &wire).is_empty(),
        "telemetry flows again"
    );
}

#[test]
fn a_flooding_host_gets_every_answer_and_the_walk_goes_on() {
    let (mut board, wire, mut client, _) = walking();
    let c0 = status(&mut board, &mut client).counters;
    // Between every two bus cycles: 50 requests and 5 garbage frames in one write.
    let (mut asked, mut answered, mut rejected) = (0u32, 0u32, 0u32);
    for _ in 0..200 {
        let mut bytes = Vec::new();
        let mut seqs = Vec::new();
        for i in 0..50 {
            let (seq, f) = client.request_frame(&Request::GetStatus).unwrap();
            seqs.push(seq);
            bytes.extend(f);
            if i % 10 == 0 {
                bytes.extend([0x13, 0x37, 0x42, 0x00]);
            }
        }
        asked += 50;
        for m in exchange(&mut board, &bytes) {
            match m {
                DeviceMessage::Reply { seq, response } => {
                    assert_eq!(seq, seqs[answered as usize % 50]);
                    assert!(matches!(response, Response::Status(_)));
                    answered += 1;
                }
                DeviceMessage::Rejected(_) => rejected += 1,
                other => panic!("{other:?}"),
            }
        }
        cycle(&mut board, &wire);
        assert_eq!(state(&board), State::Walking);
    }
    assert_eq!(answered, asked);
    assert_eq!(rejected, 200 * 5);
    let c1 = status(&mut board, &mut client).counters;
    assert_eq!(c1.rejected_frames - c0.rejected_frames, 1000);
    assert_eq!(c1.cycles - c0.cycles, 200);
    assert_eq!(c1.missed_deadlines, c0.missed_deadlines);
}

#[test]
fn a_reset_during_an_upload_keeps_the_stored_gait_at_every_cut() {
    // Through the link, the power fails after n flash ticks of an upload replacing slot 0, for n
    // spread over the whole upload (store::tests cuts at every single tick of the store alone).
    // Afterwards slot 0 holds the old table or the new one, nothing else, and it plays.
    let old = SyntheticGait::new(100, 1.0).build();
    let new = SyntheticGait::new(60, 0.8).build();
    let (old_crc, new_crc) = (table_crc(&old), table_crc(&new));
    let (flash, total) = {
        let (mut board, wire) = rig(1_000_000, 100);
        let mut client = Client::new();
        run_until(&mut board, &wire, 5, |s| s == State::Idle);
        upload(&mut board, &mut client, 0, &old);
        assert_eq!(slots(&mut board, &mut client)[0], Some(old_crc));
        let flash = board.controller.into_inner().into_flash();
        let t0 = flash.ticks;
        let mut board = board_on(flash.clone(), Config::default(), wire.clone(), &wire);
        let mut client = Client::new();
        upload(&mut board, &mut client, 0, &new);
        assert_eq!(slots(&mut board, &mut client)[0], Some(new_crc));
        let after = board.controller.into_inner().into_flash();
        (flash, after.ticks - t0)
    };
    let (mut saw_old, mut saw_new) = (false, false);
    let cuts = (0..total)
        .step_by((total / 40).max(1) as usize)
        .chain([total - 1, total]);
    for n in cuts {
        let wire = wire(1_000_000);
        let mut f = flash.clone();
        f.lose_power_after(n);
        let mut board = board_on(f, Config::default(), wire.clone(), &wire);
        let mut client = Client::new();
        for req in upload_requests(0, &new) {
            let _ = ask(&mut board, &mut client, req);
        }
        let mut f = board.controller.into_inner().into_flash();
        f.power_cycle();
        let mut board = board_on(f, Config::default(), wire.clone(), &wire);
        let mut client = Client::new();
        run_until(&mut board, &wire, 5, |s| s == State::Idle);
        let crc = slots(&mut board, &mut client)[0];
        assert!(
            crc == Some(old_crc) || crc == Some(new_crc),
            "cut at {n}/{total}: {crc:x?}"
        );
        saw_old |= crc == Some(old_crc);
        saw_new |= crc == Some(new_crc);
        play(&mut board, &mut client, protocol::Steps::Count(1));
        run_until(&mut board, &wire, 500, |s| s == State::Walking);
    }
    assert!(saw_old && saw_new, "cuts covered both outcomes");
}

#[test]
fn a_reset_during_walking_comes_up_idle_with_the_gait_kept() {
    let (mut board, wire, mut client, table) = walking();
    for _ in 0..137 {
        cycle(&mut board, &wire);
    }
    let stored = slots(&mut board, &mut client);
    // The controller resets (watchdog, brown-out of the board alone): the servos keep their power.
    let flash = board.controller.into_inner().into_flash();
    let mut board = board_on(flash, Config::default(), wire.clone(), &wire);
    let mut client = Client::new();
    run_until(&mut board, &wire, 10, |s| s == State::Idle);
    // Nothing moves on its own after a reset.
    for _ in 0..50 {
        cycle(&mut board, &wire);
    }
    assert_eq!(state(&board), State::Idle);
    assert_eq!(slots(&mut board, &mut client), stored);
    assert_eq!(stored[0], Some(table_crc(&table)));
    play(&mut board, &mut client, protocol::Steps::Count(2));
    run_until(&mut board, &wire, 500, |s| s == State::Walking);
    run_until(&mut board, &wire, 300, |s| s == State::Standing);
}

#[test]
fn after_a_reset_during_walking_torque_off_and_emergency_stop_reach_the_servos() {
    let (mut board, wire, _, _) = walking();
    for _ in 0..50 {
        cycle(&mut board, &wire);
    }
    let flash = board.controller.into_inner().into_flash();
    let mut board = board_on(flash, Config::default(), wire.clone(), &wire);
    let mut client = Client::new();
    run_until(&mut board, &wire, 10, |s| s == State::Idle);
    assert_eq!(
        ask(&mut board, &mut client, Request::EmergencyStop),
        Response::Ack
    );
    for _ in 0..5 {
        cycle(&mut board, &wire);
    }
    wire.with_chain(|c| {
        for s in c.servos() {
            assert!(
                !s.torque_enabled(),
                "servo {} still has torque after EmergencyStop",
                s.id()
            );
        }
    });
}

#[test]
fn a_table_larger_than_the_flash_bank_is_refused_and_the_stored_gait_stays() {
    let (mut board, wire) = rig(1_000_000, 100);
    let mut client = Client::new();
    run_until(&mut board, &wire, 5, |s| s == State::Idle);
    let table = SyntheticGait::new(100, 1.0).build();
    upload(&mut board, &mut client, 0, &table);
    let max = board.controller.borrow().store().max_table_len();
    let before = slots(&mut board, &mut client);
    // A valid header whose table is larger than the bank: the most slices a table may have.
    let header = protocol::GaitTable::parse(&table).unwrap().header();
    let mut large = header;
    large.slice_count = protocol::gait::MAX_SLICES;
    assert!(large.table_len() > max, "the test table fits the bank");
    for slot in 0..4 {
        let r = ask(
            &mut board,
            &mut client,
            Request::UploadBegin {
                slot,
                header: large,
                total_len: large.table_len(),
            },
        );
        assert_eq!(
            r,
            Response::Error(ProtocolError::Upload(protocol::UploadError::TooLarge {
                total_len: large.table_len(),
                capacity: max
            })),
            "slot {slot}"
        );
    }
    // Every slot filled, then one more: there is no fifth slot, and the four stay.
    for slot in 1..4 {
        upload(&mut board, &mut client, slot, &table);
    }
    let r = ask(
        &mut board,
        &mut client,
        Request::UploadBegin {
            slot: 4,
            header,
            total_len: table.len() as u32,
        },
    );
    assert_eq!(
        r,
        Response::Error(ProtocolError::Upload(protocol::UploadError::NoSuchSlot {
            slot: 4,
            slots: 4
        }))
    );
    let after = slots(&mut board, &mut client);
    assert_eq!(after[0], before[0]);
    assert!(after.iter().all(|c| *c == Some(table_crc(&table))));
    // And the board still walks from slot 0 (after Boot has found the servos of the new map).
    run_until(&mut board, &wire, 10, |s| s == State::Idle);
    play(&mut board, &mut client, protocol::Steps::Count(1));
    run_until(&mut board, &wire, 500, |s| s == State::Walking);
}

/// The soak: `secs` of simulated walking (100 Hz) with random bus noise, servo glitches (corrupt
/// replies for fewer cycles than the miss limit), servos going silent (a fault, cleared and walked
/// on), host garbage frames and a host that stops reading for a while. Checks that no cycle
/// hangs or panics, every injected fault is reported with its joint, every garbage frame is counted,
/// no glitch becomes a fault, and the stored gait is unchanged at the end. Returns the figures.
fn soak(secs: u64) -> SoakFigures {
    let (mut board, wire, mut client, table) = walking();
    let limit = Config::default().miss_limit;
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut rnd = move |n: u64| {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        x % n
    };
    let mut f = SoakFigures::default();
    let c0 = status(&mut board, &mut client).counters;
    let mut glitch_until = 0u64;
    let mut deaf_until = 0u64;
    let started = std::time::Instant::now();
    let cycles = secs * 100;
    for k in 0..cycles {
        if state(&board) == State::Walking {
            if rnd(200) == 0 {
                let burst: Vec<u8> = (0..rnd(48)).map(|_| rnd(256) as u8).collect();
                wire.inject_noise(&burst);
                f.noise_bursts += 1;
            }
            if k >= glitch_until && rnd(500) == 0 {
                let id = rnd(JOINTS as u64) as u8 + 1;
                set_faults(&wire, id, Faults::BAD_CRC);
                // Below the miss limit, and no other glitch until this one has been healed
                // for a few cycles.
                for _ in 0..1 + rnd(u64::from(limit) - 1) {
                    cycle(&mut board, &wire);
                }
                set_faults(&wire, id, Faults::default());
                glitch_until = k + 10;
                f.glitches += 1;
            }
            if rnd(3000) == 0 {
                let id = rnd(JOINTS as u64) as u8 + 1;
                set_faults(&wire, id, Faults::SILENT);
                run_until(&mut board, &wire, usize::from(limit) + 1, |s| {
                    matches!(s, State::Safe(_))
                });
                let s = status(&mut board, &mut client);
                let fault = s.fault.expect("a silent servo is reported");
                assert_eq!(fault.joint, Some(id - 1), "cycle {k}");
                assert_eq!(fault.kind, FaultKind::ServoMissing { cycles: limit });
                f.silent_servos += 1;
                f.faults_reported += 1;
                set_faults(&wire, id, Faults::default());
                assert_eq!(
                    ask(&mut board, &mut client, Request::ClearFault),
                    Response::Ack
                );
                run_until(&mut board, &wire, 10, |s| s == State::Idle);
                play(&mut board, &mut client, protocol::Steps::Continuous);
                run_until(&mut board, &wire, 1000, |s| s == State::Walking);
            }
        }
        if rnd(1000) == 0 {
            let len = 1 + rnd(300) as usize;
            let mut junk: Vec<u8> = (0..len).map(|_| rnd(255) as u8 + 1).collect();
            junk.push(0);
            let answer = exchange(&mut board, &junk);
            assert!(
                matches!(answer.as_slice(), [DeviceMessage::Rejected(_)]),
                "{answer:?}"
            );
            f.garbage_frames += 1;
        }
        if k >= deaf_until && rnd(6000) == 0 {
            deaf_until = k + 100 + rnd(400); // the host stops reading for 1 to 5 s
            f.host_silences += 1;
        }
        if k < deaf_until {
            wire.block_on(board.run_cycle());
        } else {
            cycle(&mut board, &wire);
        }
        if k % 100 == 0 {
            let s = status(&mut board, &mut client);
            assert!(s.fault.is_none(), "cycle {k}: unexpected fault {s:?}");
        }
    }
    let c1 = status(&mut board, &mut client).counters;
    f.sim_s = (wire.now_us() as f64) * 1e-6;
    f.wall_s = started.elapsed().as_secs_f64();
    f.cycles = u64::from(c1.cycles - c0.cycles);
    f.missed_deadlines = u64::from(c1.missed_deadlines - c0.missed_deadlines);
    f.timeouts = u64::from(c1.bus_timeouts - c0.bus_timeouts);
    f.crc_errors = u64::from(c1.crc_errors - c0.crc_errors);
    f.rejected = u64::from(c1.rejected_frames - c0.rejected_frames);
    f.telemetry_dropped = u64::from(c1.telemetry_dropped - c0.telemetry_dropped);
    assert_eq!(f.rejected, f.garbage_frames, "every garbage frame counted");
    assert_eq!(f.faults_reported, f.silent_servos);
    assert_eq!(
        slots(&mut board, &mut client)[0],
        Some(table_crc(&table)),
        "gait kept"
    );
    assert_eq!(board.controller.borrow().store().table(0), Some(&table[..]));
    assert!(
        f.cycles >= cycles,
        "{} bus cycles for {cycles} loop turns",
        f.cycles
    );
    eprintln!("soak: {f:?}");
    f
}

#[derive(Debug, Default)]
struct SoakFigures {
    sim_s: f64,
    wall_s: f64,
    cycles: u64,
    missed_deadlines: u64,
    timeouts: u64,
    crc_errors: u64,
    rejected: u64,
    telemetry_dropped: u64,
    noise_bursts: u64,
    glitches: u64,
    silent_servos: u64,
    faults_reported: u64,
    garbage_frames: u64,
    host_silences: u64,
}

#[test]
fn soak_two_simulated_minutes() {
    let f = soak(120);
    assert!(
        f.silent_servos >= 1 && f.glitches >= 5 && f.noise_bursts >= 20,
        "{f:?}"
    );
}

/// One simulated hour: `cargo test -p firmware --release --lib soak_one_simulated_hour -- --ignored
/// --nocapture` (figures in docs/reliability.md).
#[test]
#[ignore = "long: one simulated hour (minutes of wall time in release)"]
fn soak_one_simulated_hour() {
    let f = soak(3600);
    assert!(f.sim_s >= 3600.0, "{f:?}");
}

#[test]
fn any_request_keeps_an_endless_run_alive_and_a_silent_host_stops_it_at_the_end_of_a_step() {
    // The host-loss rule through the link: 50 silent cycles allowed, steps of 100 cycles.
    let wire = wire(1_000_000);
    let config = Config {
        host_timeout_cycles: 50,
        ..Config::default()
    };
    let mut board = board_on(NorDouble::new(SECTORS), config, wire.clone(), &wire);
    let mut client = Client::new();
    run_until(&mut board, &wire, 5, |s| s == State::Idle);
    upload(
        &mut board,
        &mut client,
        0,
        &SyntheticGait::new(100, 1.0).build(),
    );
    run_until(&mut board, &wire, 5, |s| s == State::Idle);
    play(&mut board, &mut client, protocol::Steps::Continuous);
    run_until(&mut board, &wire, 500, |s| s == State::Walking);
    // A host that only asks for the status every 40 cycles (as `dbot run` does every 100 ms)
    // keeps it walking for 4 steps.
    for i in 0..400 {
        if i % 40 == 0 {
            status(&mut board, &mut client);
        }
        cycle(&mut board, &wire);
        assert_eq!(state(&board), State::Walking, "cycle {i} with a live host");
    }
    // Silent: it stops at the end of the step it is in, standing, no fault.
    let n = run_until(&mut board, &wire, 200, |s| s == State::Standing);
    assert!(
        (51..=51 + 100 + 1).contains(&n),
        "stood after {n} silent cycles"
    );
    let s = status(&mut board, &mut client);
    assert_eq!(s.state, RunState::Standing);
    assert!(s.fault.is_none());
}

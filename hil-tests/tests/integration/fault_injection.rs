//! Servo and bus faults injected into the emulator's servo chain (`hil-bus` controls, see
//! hil-tests/README.md) while the real firmware image walks: a silent servo, corrupt replies, a
//! stuck servo and bus noise, each checked against the behaviour docs/reliability.md writes down
//! for the firmware library (the same rows), from what the host sees: GetStatus (state, fault and
//! joint, counters) and telemetry. The first tests check the controls themselves on the servo
//! chain alone (no emulator).

use anyhow::{Context, Result, bail, ensure};
use dynamixel::parser::Parser;
use dynamixel::sim::VirtualChain;
use hil_tests::drive::{T, start_playing, start_with_servos, telemetry, upload_sine_gait};
use hil_tests::emulator::Emulator;
use hil_tests::gait::JOINTS;
use hil_tests::link::Link;
use hil_tests::servo_bus::ServoBus;
use protocol::message::{Direction, FaultKind, RunState, Status, Steps};
use protocol::{Request, Response, Telemetry, feedback_flags};
use serde_json::json;
use std::time::{Duration, Instant};

const HIL_BUS: &str = env!("CARGO_BIN_EXE_hil-bus");
/// The firmware's default miss limit (controller::Config::miss_limit).
const MISS_LIMIT: u8 = 3;
/// One servo tick in telemetry units (1e-4 rad): 2 pi / 4096 rad.
const TICK: f64 = std::f64::consts::TAU / 4096.0 * 1e4;

// ---- the controls on the servo chain alone ----

/// A Sync Read of Present Position of IDs 1..=3 (e-manual: FF FF FD 00, broadcast ID, instruction
/// 0x82, address 132, 4 bytes), as the burst the board would send at `end_ns`.
fn sync_read(bus: &mut ServoBus, end_ns: u64) -> Vec<hil_tests::servo_bus::Segment> {
    let mut buf = [0u8; 64];
    let n = dynamixel::encode::sync_read(&mut buf, 132, 4, &[1, 2, 3]).unwrap();
    bus.burst(&buf[..n], end_ns, 1_000_000)
}

/// The IDs of the status packets in `segments` that pass their CRC, and how many failed it.
fn statuses(segments: &[hil_tests::servo_bus::Segment]) -> (Vec<u8>, usize) {
    let mut p: Parser = Parser::default();
    let (mut ok, mut bad) = (vec![], 0);
    for s in segments {
        p.feed(&s.rx);
        while let Some(f) = p.next_frame() {
            match f {
                Ok(f) => ok.push(f.id),
                Err(_) => bad += 1,
            }
        }
    }
    (ok, bad)
}

/// Servos 1 to 3 of the robot, as its model file maps them.
fn chain_bus() -> ServoBus {
    let first: Vec<_> = hil_tests::gait::robot_servos()
        .into_iter()
        .filter(|s| s.0 <= 3)
        .collect();
    let mut chain = VirtualChain::new(&first, 1_000_000).unwrap();
    chain.set_return_delay_all(0);
    ServoBus::new(chain)
}

#[test]
fn silent_and_corrupt_controls_change_what_the_chain_answers() -> Result<()> {
    let mut bus = chain_bus();
    assert_eq!(statuses(&sync_read(&mut bus, 1_000)), (vec![1, 2, 3], 0));
    bus.line(r#"{"control":{"silent":[2,true]}}"#)?;
    assert_eq!(statuses(&sync_read(&mut bus, 2_000)), (vec![1, 3], 0));
    bus.line(r#"{"control":{"silent":[2,false]}}"#)?;
    bus.line(r#"{"control":{"corrupt":[3,2]}}"#)?;
    // Two replies of servo 3 fail their CRC, then it is good again.
    for t in [3_000, 4_000] {
        assert_eq!(statuses(&sync_read(&mut bus, t)), (vec![1, 2], 1));
    }
    assert_eq!(statuses(&sync_read(&mut bus, 5_000)), (vec![1, 2, 3], 0));
    bus.line(r#"{"control":{"corrupt":[1,true]}}"#)?;
    for t in [6_000, 7_000, 8_000] {
        assert_eq!(statuses(&sync_read(&mut bus, t)), (vec![2, 3], 1));
    }
    Ok(())
}

#[test]
fn stuck_and_noise_controls_act_and_bad_controls_name_the_field() -> Result<()> {
    let mut bus = chain_bus();
    bus.line(r#"{"control":{"stuck":[1,true]}}"#)?;
    assert!(bus.chain().servo(1).unwrap().faults.stuck);
    // Noise: 10 random bytes and 2 false headers (7 bytes each) collide with the next replies
    // only: the window's first 24 bytes are replaced, the timing is that of a clean window.
    let clean = sync_read(&mut chain_bus(), 1_000);
    // A status with 4 bytes of data is 11 + 4 = 15 bytes (e-manual packet layout).
    assert_eq!(
        clean.iter().map(|s| s.rx.len()).collect::<Vec<_>>(),
        [15; 3]
    );
    bus.line(r#"{"control":{"noise":{"bytes":10,"headers":2}}}"#)?;
    let with = sync_read(&mut bus, 1_000);
    let delays =
        |v: &[hil_tests::servo_bus::Segment]| v.iter().map(|s| s.delay_ns).collect::<Vec<_>>();
    assert_eq!(delays(&with), delays(&clean));
    let (w, c): (Vec<u8>, Vec<u8>) = (
        with.iter().flat_map(|s| s.rx.clone()).collect(),
        clean.iter().flat_map(|s| s.rx.clone()).collect(),
    );
    assert_eq!(w.len(), c.len());
    assert_eq!(&w[10..17], &[0xFF, 0xFF, 0xFD, 0x00, 0x05, 0x20, 0x00]);
    assert_eq!(&w[17..24], &[0xFF, 0xFF, 0xFD, 0x00, 0x05, 0x20, 0x00]);
    assert_eq!(&w[24..], &c[24..], "past the noise the replies are intact");
    assert_eq!(
        statuses(&sync_read(&mut bus, 2_000)),
        (vec![1, 2, 3], 0),
        "noise used up"
    );
    for (line, names) in [
        (r#"{"control":{"silent":[99,true]}}"#, "99"),
        (r#"{"control":{"silent":[2,"yes"]}}"#, "silent[1]"),
        (r#"{"control":{"corrupt":[2,-1]}}"#, "corrupt[1]"),
        (r#"{"control":{"stuck":["a",true]}}"#, "stuck[0]"),
        (r#"{"control":{"noise":{"bytes":100000}}}"#, "noise.bytes"),
        (r#"{"control":{"noise":{}}}"#, "noise"),
    ] {
        let e = format!("{:#}", bus.line(line).unwrap_err());
        ensure!(
            e.contains(names),
            "{line}: error {e:?} does not name {names}"
        );
    }
    Ok(())
}

// ---- the emulator ----

/// The board walking the sine gait continuously with telemetry every cycle, past the ramp.
fn walking(test: &str) -> Result<Option<(hil_tests::Target, Link)>> {
    let Some((board, mut link)) = start_with_servos(test, HIL_BUS, JOINTS, 1_000_000)? else {
        return Ok(None);
    };
    if board.emulator().is_none() {
        hil_tests::target::skip(
            test,
            "injecting servo faults needs the emulator's servo chain",
        )?;
        return Ok(None);
    }
    upload_sine_gait(&mut link, "faults", Some(1))?;
    start_playing(&mut link, 0, Direction::Forward, Steps::Continuous)?;
    let emu = board.emulator().context("emulator")?;
    wait_state(emu, &mut link, RunState::Walking)?;
    // A little walking, so that the windows below are all walking.
    emu.run_for(Duration::from_millis(300))?;
    link.collect(Duration::from_millis(50))?;
    link.unsolicited.clear();
    Ok(Some((board, link)))
}

fn wait_state(emu: &Emulator, link: &mut Link, want: RunState) -> Result<Status> {
    for _ in 0..200 {
        let s: Status = link.request(&Request::GetStatus, T)?;
        if s.state == want {
            return Ok(s);
        }
        emu.run_for(Duration::from_millis(50))?;
        link.unsolicited.clear();
    }
    bail!("not {want:?} after 10 s of simulated time")
}

/// Every telemetry record received until at least one has come, letting simulated time pass
/// (at most a second of it) rather than wall time: as many as the board sent, never none.
fn telemetry_since_now(emu: &Emulator, link: &mut Link) -> Result<Vec<Telemetry>> {
    let mut records = Vec::new();
    for _ in 0..100 {
        records.extend(telemetry(&link.collect(Duration::from_millis(10))?));
        if !records.is_empty() {
            return Ok(records);
        }
        emu.run_for(Duration::from_millis(10))?;
    }
    bail!("no telemetry record within 1 s of simulated time")
}

/// Reads telemetry and asks for the status until the board reports a fault (at most `sim_limit`
/// of simulated time); returns the status and every telemetry record seen, in cycle order.
fn until_fault(
    emu: &Emulator,
    link: &mut Link,
    sim_limit: Duration,
) -> Result<(Status, Vec<Telemetry>)> {
    let deadline = emu.sim_time()? + sim_limit;
    let mut records = Vec::new();
    let started = Instant::now();
    loop {
        records.extend(telemetry(&link.collect(Duration::from_millis(30))?));
        let s: Status = link.request(&Request::GetStatus, T)?;
        records.extend(telemetry(&link.unsolicited.drain(..).collect::<Vec<_>>()));
        if s.fault.is_some() {
            // The records of the last cycles may still be on their way.
            records.extend(telemetry(&link.collect(Duration::from_millis(200))?));
            records.sort_by_key(|t| t.cycle);
            records.dedup_by_key(|t| t.cycle);
            return Ok((s, records));
        }
        ensure!(
            emu.sim_time()? < deadline && started.elapsed() < Duration::from_secs(120),
            "no fault within {sim_limit:?} of simulated time: {s:?}"
        );
    }
}

/// `Play` is refused while the fault stands; after `ClearFault` the board plays again and walks a
/// second without a fault.
fn refused_then_walks_again(emu: &Emulator, link: &mut Link) -> Result<()> {
    let play = Request::Play(protocol::message::PlayCommand {
        slot: 0,
        direction: Direction::Forward,
        period_scale: 1000,
        steps: Steps::Continuous,
    });
    match link.request::<Response>(&play, T) {
        Err(e) if format!("{e:#}").contains("WrongState") => {}
        other => bail!("Play in the fault state answered {other:?}"),
    }
    let r: Response = link.request(&Request::ClearFault, T)?;
    ensure!(r == Response::Ack, "ClearFault: {r:?}");
    start_playing(link, 0, Direction::Forward, Steps::Continuous)?;
    wait_state(emu, link, RunState::Walking)?;
    emu.run_for(Duration::from_secs(1))?;
    let s: Status = link.request(&Request::GetStatus, T)?;
    ensure!(
        s.state == RunState::Walking && s.fault.is_none(),
        "after clearing: {s:?}"
    );
    Ok(())
}

/// Whether any joint's goal changed from `a` to `b` (the board wrote new goals in `b`'s cycle).
fn goals_moved(a: &Telemetry, b: &Telemetry) -> bool {
    a.joints
        .iter()
        .zip(&b.joints)
        .any(|(x, y)| x.commanded != y.commanded)
}

#[test]
fn a_silent_servo_stops_the_walk_at_the_third_miss_naming_its_joint() -> Result<()> {
    let Some((board, mut link)) = walking("fault_silent")? else {
        return Ok(());
    };
    let emu = board.emulator().context("emulator")?;
    let before: Status = link.request(&Request::GetStatus, T)?;
    // At least one record from before the silence, in hand before it starts: the board may
    // answer GetStatus and take the silence before it sends another record (how many cycles pass
    // between the two depends on how fast the host runs the emulator), and without one nothing
    // shows the goals of the cycle before the first miss.
    let before_silence = telemetry_since_now(emu, &mut link)?;
    // Servo 7 is joint 6 of the table (IDs 1..=22 in joint order).
    emu.bus_control(json!({"silent": [7, true]}))?;
    let (s, mut records) = until_fault(emu, &mut link, Duration::from_secs(2))?;
    records.extend(before_silence);
    records.sort_by_key(|t| t.cycle);
    records.dedup_by_key(|t| t.cycle);
    let fault = s.fault.context("fault")?;
    assert_eq!(
        (fault.kind, fault.joint),
        (FaultKind::ServoMissing { cycles: MISS_LIMIT }, Some(6))
    );
    assert_eq!(s.state, RunState::Fault);
    assert!(s.playback.is_none(), "{s:?}");
    // Every miss was counted (the board goes on reading the silent servo in the safe state).
    ensure!(
        s.counters.bus_timeouts >= before.counters.bus_timeouts + u32::from(MISS_LIMIT),
        "{:?} -> {:?}",
        before.counters,
        s.counters
    );
    // Telemetry: the first miss, then goals written for the 1st..3rd missed cycle, none after.
    let first = records
        .iter()
        .position(|t| t.joints[6].flags & feedback_flags::NO_REPLY != 0)
        .context("no record shows the missing reply")?;
    ensure!(first > 0, "the first miss is in the first record");
    let run = &records[first - 1..];
    for (k, w) in run.windows(2).enumerate().take(8) {
        ensure!(
            w[1].cycle == w[0].cycle + 1,
            "telemetry record lost around cycle {}",
            w[0].cycle
        );
        let moved = goals_moved(&w[0], &w[1]);
        let want = k < usize::from(MISS_LIMIT);
        ensure!(
            moved == want,
            "missed cycle {}: goals written {moved}, expected {want}",
            k + 1
        );
    }
    // The others answered all along: only joint 6 lacks replies in those cycles.
    for t in &run[1..=usize::from(MISS_LIMIT)] {
        let others: Vec<usize> = (0..JOINTS)
            .filter(|&j| j != 6 && t.joints[j].flags & feedback_flags::NO_REPLY != 0)
            .collect();
        ensure!(
            others.is_empty(),
            "cycle {}: joints {others:?} missed too",
            t.cycle
        );
    }
    emu.bus_control(json!({"silent": [7, false]}))?;
    refused_then_walks_again(emu, &mut link)
}

#[test]
fn corrupt_replies_are_counted_and_only_a_run_of_them_is_a_fault() -> Result<()> {
    let Some((board, mut link)) = walking("fault_corrupt")? else {
        return Ok(());
    };
    let emu = board.emulator().context("emulator")?;
    let c0 = link.request::<Status>(&Request::GetStatus, T)?.counters;
    // Runs of miss limit - 1 corrupt replies of servo 12 (joint 11), five times: glitches.
    for round in 0..5 {
        emu.bus_control(json!({"corrupt": [12, MISS_LIMIT - 1]}))?;
        emu.run_for(Duration::from_millis(100))?;
        let s: Status = link.request(&Request::GetStatus, T)?;
        link.unsolicited.clear();
        ensure!(
            s.state == RunState::Walking && s.fault.is_none(),
            "round {round}: {s:?}"
        );
    }
    let c1 = link.request::<Status>(&Request::GetStatus, T)?.counters;
    assert_eq!(
        c1.crc_errors - c0.crc_errors,
        5 * u32::from(MISS_LIMIT - 1),
        "one CRC error per corrupt reply"
    );
    assert_eq!(c1.bus_timeouts, c0.bus_timeouts, "no reply went missing");
    // Every reply corrupt: as good as silent.
    emu.bus_control(json!({"corrupt": [12, true]}))?;
    let (s, _) = until_fault(emu, &mut link, Duration::from_secs(2))?;
    let fault = s.fault.context("fault")?;
    assert_eq!(
        (fault.kind, fault.joint),
        (FaultKind::ServoMissing { cycles: MISS_LIMIT }, Some(11))
    );
    assert!(s.counters.crc_errors >= c1.crc_errors + u32::from(MISS_LIMIT));
    emu.bus_control(json!({"corrupt": [12, false]}))?;
    refused_then_walks_again(emu, &mut link)
}

#[test]
fn a_stuck_servo_stops_the_walk_within_two_windows_naming_its_joint() -> Result<()> {
    let Some((board, mut link)) = walking("fault_stuck")? else {
        return Ok(());
    };
    let emu = board.emulator().context("emulator")?;
    // Servo 3 (joint 2, an MX-64) jams: it answers, no error bit, its output stays.
    let t0 = emu.sim_time()?;
    emu.bus_control(json!({"stuck": [3, true]}))?;
    let (s, records) = until_fault(emu, &mut link, Duration::from_secs(3))?;
    let dt = emu.sim_time()? - t0;
    let fault = s.fault.context("fault")?;
    let FaultKind::ServoStuck {
        goal_range,
        present_range,
    } = fault.kind
    else {
        bail!("fault {fault:?}, expected ServoStuck");
    };
    assert_eq!(fault.joint, Some(2));
    assert_eq!(s.state, RunState::Fault);
    // The rule (firmware safety::stuck): 50-cycle windows, goal over > 40 ticks, present <= 2.
    ensure!(goal_range > 40 && present_range <= 2, "{fault:?}");
    // Reported within two windows (2 x 0.5 s at 100 Hz) of the jam, plus the polling step here.
    ensure!(dt <= Duration::from_millis(1_300), "reported after {dt:?}");
    // The last 50 records before the fault: joint 2's goal moved, its output did not.
    let walking: Vec<&Telemetry> = records
        .windows(2)
        .filter(|w| goals_moved(&w[0], &w[1]))
        .map(|w| &w[1])
        .collect();
    ensure!(
        walking.len() >= 50,
        "only {} walking records",
        walking.len()
    );
    let last = &walking[walking.len() - 50..];
    let span = |f: &dyn Fn(&Telemetry) -> i16| {
        let v: Vec<i16> = last.iter().map(|t| f(t)).collect();
        f64::from(v.iter().max().unwrap() - v.iter().min().unwrap())
    };
    let commanded = span(&|t| t.joints[2].commanded);
    let present = span(&|t| t.joints[2].present);
    ensure!(commanded > 40.0 * TICK, "commanded span {commanded}");
    ensure!(present <= 2.0 * TICK + 1.0, "present span {present}");
    // A neighbour followed its goal.
    ensure!(span(&|t| t.joints[3].present) > 40.0 * TICK);
    println!(
        "stuck: {fault:?} after {dt:?}; joint 2 commanded span {:.0} ticks, present {:.1}",
        commanded / TICK,
        present / TICK
    );
    emu.bus_control(json!({"stuck": [3, false]}))?;
    refused_then_walks_again(emu, &mut link)
}

#[test]
fn bus_noise_bursts_are_survived_and_counted() -> Result<()> {
    let Some((board, mut link)) = walking("fault_noise")? else {
        return Ok(());
    };
    let emu = board.emulator().context("emulator")?;
    let c0 = link.request::<Status>(&Request::GetStatus, T)?.counters;
    // 20 bursts, 50 ms of simulated time apart: 30 random bytes and two false headers (each
    // claiming 32 bytes) in place of the first 44 reply bytes of one cycle. A reply is 21 bytes
    // (10 data bytes), so each burst overlaps the replies of servos 1, 2 and 3.
    let bursts = 20;
    let noise_bytes = 30 + 2 * 7;
    let hit_per_burst = (noise_bytes as u32).div_ceil(21);
    let mut before = c0;
    for k in 0..bursts {
        emu.bus_control(json!({"noise": {"bytes": 30, "headers": 2}}))?;
        emu.run_for(Duration::from_millis(50))?;
        let s: Status = link.request(&Request::GetStatus, T)?;
        link.unsolicited.clear();
        ensure!(
            s.state == RunState::Walking && s.fault.is_none(),
            "during the noise: {s:?}"
        );
        // The bus master follows the reply schedule: the replies behind the noise are still
        // inside their time and count (docs/reliability.md, bus noise).
        let lost = (s.counters.crc_errors - before.crc_errors)
            + (s.counters.bus_timeouts - before.bus_timeouts);
        ensure!(
            (1..=hit_per_burst).contains(&lost),
            "burst {k}: {lost} replies lost, the burst overlapped {hit_per_burst}"
        );
        before = s.counters;
    }
    let c1 = link.request::<Status>(&Request::GetStatus, T)?.counters;
    let (crc, timeouts) = (
        c1.crc_errors - c0.crc_errors,
        c1.bus_timeouts - c0.bus_timeouts,
    );
    println!(
        "noise: {bursts} bursts, {crc} CRC errors, {timeouts} timeouts, {} cycles, {} missed deadlines",
        c1.cycles - c0.cycles,
        c1.missed_deadlines - c0.missed_deadlines
    );
    assert_eq!(
        c1.missed_deadlines, c0.missed_deadlines,
        "no missed cycle start"
    );
    // 20 x 50 ms at 100 Hz: about 100 cycles (the status requests take a little simulated time).
    ensure!(c1.cycles - c0.cycles >= 95, "{:?} -> {:?}", c0, c1);
    ensure!(
        crc + timeouts <= bursts * hit_per_burst,
        "{crc} + {timeouts} replies lost"
    );
    Ok(())
}

/// A servo heating over a walk (the chain's thermal knob: servo 3, an MX-64 carrying 1 N m, with
/// 25x the default thermal resistance, started at 68 degC; ESTIMATE model, deterministic): the
/// board warns at 70 degC (status and telemetry flag joint 2, its temperature in the record),
/// then stops the walk at the end of its step at 75 degC naming the joint and servo, before the
/// servo's own 80 degC shutdown (which would be a ServoError fault).
#[test]
fn a_heating_servo_warns_then_stops_the_walk_at_a_steps_end_naming_it() -> Result<()> {
    let Some((board, mut link)) = walking("heat_stop")? else {
        return Ok(());
    };
    let emu = board.emulator().context("emulator")?;
    // Hand-worked: I = 4.1 A * 1 / 6.0 = 0.68 A, P = 0.68^2 * 12 / 4.1 = 1.37 W, steady at
    // 36 + 1.37 * 200 = 310 degC, rising (310 - 70) / 60 = 4 K/s at 70: 75 about 1.8 s after
    // 68 degC, 80 more than a second after that, longer than a step and a round of reads.
    emu.bus_control(json!({"external_torque": [3, 1.0]}))?;
    emu.bus_control(json!({"thermal": [3, 200.0, 60.0]}))?;
    emu.bus_control(json!({"temperature": [3, 68.0]}))?;
    let deadline = emu.sim_time()? + Duration::from_secs(6);
    let started = Instant::now();
    let (mut warned, mut hot_record, mut saw_stopping) = (None, None, false);
    let stopped = loop {
        let records = telemetry(&link.collect(Duration::from_millis(30))?);
        for t in &records {
            if t.joints[2].flags & feedback_flags::HEALTH_WARN != 0 && hot_record.is_none() {
                hot_record = Some(t.health[2]);
            }
        }
        let s: Status = link.request(&Request::GetStatus, T)?;
        link.unsolicited.clear();
        ensure!(
            s.fault.is_none(),
            "the servo's own limit was reached: {s:?}"
        );
        if warned.is_none() {
            warned = s.health_warning;
        }
        saw_stopping |= s.state == RunState::Stopping;
        if s.state == RunState::Standing {
            break s;
        }
        ensure!(
            emu.sim_time()? < deadline && started.elapsed() < Duration::from_secs(120),
            "no stop within 6 s of simulated time: {s:?}"
        );
    };
    let w = warned.context("no warning before the stop")?;
    ensure!((w.joint, w.id) == (2, 3), "warning {w:?}");
    let h = hot_record.context("no telemetry record flagged joint 2")?;
    ensure!((70..75).contains(&h.temperature_c), "flagged record {h:?}");
    ensure!(h.voltage_dv > 100, "supply {h:?}");
    let stop = stopped.health_stop.context("the stop names no servo")?;
    ensure!(
        (stop.joint, stop.id, stop.kind, stop.limit) == (2, 3, protocol::HealthKind::Hot, 75),
        "stop {stop:?}"
    );
    ensure!(saw_stopping || stopped.playback.is_none(), "{stopped:?}");
    println!("heat: warned {w}; stopped {stop}");
    Ok(())
}

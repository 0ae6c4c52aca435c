//! Faults while walking, with the real firmware image and the virtual servo chain: a servo overload
//! must stop the gait safely and be reported (fault kind, joint, the servo's overload bit), and a
//! host that stops reading must not stop the gait; its telemetry resumes when it reads again.

use anyhow::{Context, Result, ensure};
use hil_tests::drive::{T, start_playing, start_with_servos, telemetry, upload_sine_gait};
use hil_tests::gait::JOINTS;
use protocol::Request;
use protocol::message::{Direction, FaultKind, RunState, Status, Steps};
use serde_json::json;
use std::time::{Duration, Instant};

const HIL_BUS: &str = env!("CARGO_BIN_EXE_hil-bus");
/// Hardware Error Status bit 5: overload (e-manual, MX(2.0) address 70).
const OVERLOAD_BIT: u8 = 1 << 5;

fn walking(test: &str) -> Result<Option<(hil_tests::Target, hil_tests::link::Link)>> {
    let Some((board, mut link)) = start_with_servos(test, HIL_BUS, JOINTS, 1_000_000)? else {
        return Ok(None);
    };
    upload_sine_gait(&mut link, "safety", Some(1))?;
    start_playing(&mut link, 0, Direction::Forward, Steps::Continuous)?;
    Ok(Some((board, link)))
}

#[test]
fn servo_overload_stops_the_gait_and_names_the_joint() -> Result<()> {
    let Some((board, mut link)) = walking("overload")? else {
        return Ok(());
    };
    let Some(emu) = board.emulator() else {
        return hil_tests::target::skip("overload", "injecting an overload needs the servo model");
    };
    emu.run_for(Duration::from_secs(1))?;
    let s: Status = link.request(&Request::GetStatus, T)?;
    ensure!(
        s.state == RunState::Walking,
        "walking before the fault: {s:?}"
    );
    // Servo ID 3 is the table's third joint (index 2), an MX-64 on LF CTr.
    emu.bus_control(json!({"overload": 3}))?;
    let started = Instant::now();
    let fault = loop {
        let s: Status = link.request(&Request::GetStatus, T)?;
        if let Some(f) = s.fault {
            break (s, f);
        }
        ensure!(
            started.elapsed() < Duration::from_secs(30),
            "no fault reported: {s:?}"
        );
        emu.run_for(Duration::from_millis(20))?;
    };
    let (first, first_fault) = fault;
    println!("fault first seen: {first_fault:?}, status: {first:?}");
    // The servo's Alert bit stops the gait in the cycle it is seen, with the error bits not yet
    // known (0); the next bus cycle reads them from Hardware Error Status (controller/feedback.rs).
    // So a status taken in between says ServoError { bits: 0 }: which of the two a poll sees
    // depended on when the host's request landed (wall clock). The joint is known at once, the
    // bits after one cycle: ask again after 5 cycles of simulated time.
    assert_eq!(first_fault.joint, Some(2), "the overloaded servo's joint");
    ensure!(
        matches!(first_fault.kind, FaultKind::ServoError { bits } if bits == 0 || bits & OVERLOAD_BIT != 0),
        "first fault {first_fault:?}, expected ServoError (bits unknown or with the overload bit)"
    );
    emu.run_for(Duration::from_millis(50))?;
    let status: Status = link.request(&Request::GetStatus, T)?;
    let fault = status.fault.context("the fault went away")?;
    println!("fault: {fault:?}, status: {status:?}");
    assert_eq!(fault.joint, Some(2), "the overloaded servo's joint");
    match fault.kind {
        FaultKind::ServoError { bits } => {
            assert_ne!(bits & OVERLOAD_BIT, 0, "overload bit in {bits:#04x}")
        }
        other => anyhow::bail!("fault kind {other:?}, expected ServoError with the overload bit"),
    }
    assert_eq!(status.state, RunState::Fault);
    assert!(status.playback.is_none(), "playback stopped: {status:?}");
    // Safe stop: the gait does not resume on its own.
    emu.run_for(Duration::from_millis(500))?;
    let later: Status = link.request(&Request::GetStatus, T)?;
    assert_eq!(later.state, RunState::Fault, "{later:?}");
    Ok(())
}

#[test]
fn a_silent_host_does_not_stop_the_gait_and_telemetry_resumes() -> Result<()> {
    let Some((board, mut link)) = walking("silent_host")? else {
        return Ok(());
    };
    let Some(emu) = board.emulator() else {
        return hil_tests::target::skip("silent_host", "timing the silence needs the emulator");
    };
    emu.run_for(Duration::from_millis(500))?;
    let before = telemetry(&link.collect(Duration::from_millis(300))?);
    let last_before = before.last().context("telemetry while walking")?.clone();
    // The host says nothing and reads nothing for 3 s of simulated time.
    let silence = Duration::from_secs(3);
    emu.run_for(silence)?;
    let s: Status = link.request(&Request::GetStatus, T)?;
    ensure!(
        s.state == RunState::Walking && s.fault.is_none(),
        "after the silence: {s:?}"
    );
    let after = telemetry(&link.collect(Duration::from_millis(500))?);
    let newest = after
        .iter()
        .map(|t| t.cycle)
        .max()
        .context("telemetry resumed")?;
    // 3 s at 100 Hz: at least 300 more cycles, and at 0.6 s per step at least 4 more steps.
    let cycles = newest - last_before.cycle;
    ensure!(cycles >= 300, "only {cycles} cycles during 3 s of silence");
    let step = after.iter().map(|t| t.step).max().unwrap_or(0);
    ensure!(
        step >= last_before.step + 4,
        "steps {} -> {step}",
        last_before.step
    );
    println!(
        "silent host: cycle {} -> {newest}, step {} -> {step}, {} records after",
        last_before.cycle,
        last_before.step,
        after.len()
    );
    Ok(())
}

#[test]
fn an_endless_run_whose_host_dies_stops_at_the_end_of_a_step() -> Result<()> {
    // `dbot run` killed during an endless run: the image's host-loss rule stops the robot once the
    // host has been silent for protocol::limits::HOST_TIMEOUT_CYCLES cycles (10 s at 100 Hz).
    let Some((board, mut link)) = walking("host_lost")? else {
        return Ok(());
    };
    let Some(emu) = board.emulator() else {
        return hil_tests::target::skip("host_lost", "timing the silence needs the emulator");
    };
    let rule = Duration::from_millis(u64::from(protocol::limits::HOST_TIMEOUT_CYCLES) * 10);
    // A host that asks for the status every 100 ms, past the rule's time: still walking.
    let mut alive = Duration::ZERO;
    while alive < rule + Duration::from_secs(1) {
        emu.run_for(Duration::from_millis(100))?;
        let s: Status = link.request(&Request::GetStatus, T)?;
        ensure!(
            matches!(s.state, RunState::Ramping | RunState::Walking),
            "with a live host: {s:?}"
        );
        alive += Duration::from_millis(100);
    }
    let s: Status = link.request(&Request::GetStatus, T)?;
    ensure!(
        s.state == RunState::Walking,
        "after 11 s with a live host: {s:?}"
    );
    // Killed: nothing from the host any more. Past the rule's time and one step, it stands.
    emu.run_for(rule + Duration::from_secs(2))?;
    let s: Status = link.request(&Request::GetStatus, T)?;
    ensure!(
        s.state == RunState::Standing && s.fault.is_none(),
        "after the host fell silent: {s:?}"
    );
    Ok(())
}

#[test]
fn bad_frames_while_walking_are_rejected_and_the_gait_goes_on() -> Result<()> {
    let Some((board, mut link)) = walking("bad_frames_walking")? else {
        return Ok(());
    };
    board.run_for(Duration::from_millis(700))?;
    let before: Status = link.request(&Request::GetStatus, T)?;
    ensure!(before.state == RunState::Walking, "{before:?}");
    link.unsolicited.clear();
    // A frame whose CRC cannot match, then one longer than any frame the board accepts.
    link.send_raw(&[0x05, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x00])?;
    link.send_raw(&vec![0x42u8; protocol::MAX_FRAME_LEN * 3])?;
    link.send_raw(&[0x00])?;
    board.run_for(Duration::from_millis(700))?;
    let after: Status = link.request(&Request::GetStatus, T)?;
    let rejected = link
        .unsolicited
        .iter()
        .filter(|m| matches!(m, protocol::DeviceMessage::Rejected(_)))
        .count();
    assert_eq!(rejected, 2, "one rejection per bad frame");
    assert_eq!(after.state, RunState::Walking, "{after:?}");
    assert!(after.fault.is_none(), "{after:?}");
    let (b, a) = (
        before.playback.context("playback")?,
        after.playback.context("playback")?,
    );
    // 0.7 s at 0.6 s per step: the step counter moved on.
    assert!(
        a.step > b.step || (a.step == b.step && a.slice != b.slice),
        "{b:?} -> {a:?}"
    );
    assert_eq!(
        after.counters.rejected_frames,
        before.counters.rejected_frames + 2
    );
    Ok(())
}

#[test]
fn a_busy_host_link_does_not_cost_servo_replies() -> Result<()> {
    let Some((board, mut link)) = walking("busy_link")? else {
        return Ok(());
    };
    board.run_for(Duration::from_millis(500))?;
    let before: Status = link.request(&Request::GetStatus, T)?;
    // As fast as the host can ask: 400 status and device-info round trips while walking.
    for _ in 0..400 {
        let _: Status = link.request(&Request::GetStatus, T)?;
        let _: protocol::message::DeviceInfo = link.request(&Request::GetDeviceInfo, T)?;
    }
    let after: Status = link.request(&Request::GetStatus, T)?;
    assert_eq!(
        after.counters.bus_timeouts, before.counters.bus_timeouts,
        "servo replies lost while the host was busy: {after:?}"
    );
    Ok(())
}

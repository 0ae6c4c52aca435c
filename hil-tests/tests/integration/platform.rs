//! The perturbation platform with the real firmware image on the emulated bus: a 23rd servo
//! (ID 23 here, after the test gait's joints 1..=22) whose goal rides in the joints' Goal Position
//! Sync Write, `rise` at the first cycle of the chosen step and back to `rest` exactly
//! `hold_cycles` cycles later; and a platform servo that does not answer refuses `Play` with
//! words naming its ID, before any goal is written.
//!
//! Independent truth: the bus frames (parsed with the dynamixel crate's parser, not the
//! firmware's code) for what the Sync Writes carry, and the board's own cycle and step counts in
//! its telemetry for when: the first cycle the board counts in step 1 and the one after it carry
//! `rise`, the cycles either side `rest`. Never the emulator's clock or wall-clock time: the
//! emulator now and then skips a cycle start, which moved a time-based estimate of step 1 by one
//! write (the test raced the emulator).

use anyhow::{Context, Result, bail, ensure};
use hil_tests::bus_trace::goal_writes;
use hil_tests::drive::{T, play_steps, start_with_servos};
use hil_tests::gait::{JOINTS, sine_gait, upload};
use hil_tests::link::Link;
use protocol::message::Direction;
use protocol::{
    DeviceMessage, MAX_CHUNK_LEN, PlatformError, PlatformMove, PlatformSetup, PlatformState,
    PlatformStatus, PlayCommand, ProtocolError, Request, Response, Steps,
};
use std::time::Duration;

const HIL_BUS: &str = env!("CARGO_BIN_EXE_hil-bus");
const PLATFORM_ID: u8 = 23;

fn setup(step: u32) -> PlatformSetup {
    PlatformSetup {
        servo_id: PLATFORM_ID,
        ..PlatformSetup::lab(PlatformMove::Rise, step)
    }
}

/// Uploads the test gait into slot 0 and sets the platform up; waits (bounded) until the board
/// has checked its servo, and returns what it found.
fn prepare(link: &mut Link, step: u32) -> Result<PlatformStatus> {
    let (builder, table) = sine_gait("platform", 40, 0.2)?;
    let r = upload(link, 0, &builder, &table, MAX_CHUNK_LEN, T)?;
    ensure!(matches!(r, Response::Committed { .. }), "{r:?}");
    let r: Response = link.request(&Request::SetPlatform(setup(step)), T)?;
    ensure!(r == Response::Ack, "SetPlatform answered {r:?}");
    for _ in 0..50 {
        let p: Option<PlatformStatus> = link.request(&Request::GetPlatform, T)?;
        let p = p.context("the board forgot the platform")?;
        if p.state != PlatformState::Checking {
            return Ok(p);
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    bail!("the board did not check the platform servo within 5 s (wall)")
}

#[test]
fn the_platform_goal_rises_at_the_first_cycle_of_its_step_and_rests_two_cycles_later() -> Result<()>
{
    let test = "platform_rise";
    let Some((board, mut link)) = start_with_servos(test, HIL_BUS, JOINTS + 1, 1_000_000)? else {
        return Ok(());
    };
    let Some(emu) = board.emulator() else {
        return hil_tests::target::skip(test, "the bus trace needs the emulator");
    };
    let p = prepare(&mut link, 1)?;
    ensure!(
        matches!(p.state, PlatformState::Ready { .. }),
        "platform servo {PLATFORM_ID} not ready: {p:?}"
    );
    emu.bus_trace_start()?;
    let records = play_steps(&mut link, 0, Direction::Forward, 3)?;
    let writes = goal_writes(&emu.bus_trace_stop_bytes()?)?;
    // Every goal write carries the 22 joints and, last by ID, the platform.
    for (_, w) in &writes {
        ensure!(
            w.len() == JOINTS + 1 && w[JOINTS].0 == PLATFORM_ID,
            "a goal Sync Write without the platform: {w:?}"
        );
    }
    // Where step 1 starts, in the board's own counts: the first cycle whose record says one step
    // is done. Its record and the one after carry `rise`, the cycles before and after `rest`
    // (each record's platform goal is what that cycle's Sync Write carried). The records around
    // it must be consecutive cycles, so a record lost on the link cannot pass for the timing.
    let k = records
        .iter()
        .position(|r| r.step == 1)
        .context("no telemetry record in step 1")?;
    ensure!(
        k >= 1 && k + 2 < records.len(),
        "too few records around step 1's start"
    );
    let around = &records[k - 1..=k + 2];
    ensure!(
        around.windows(2).all(|w| w[1].cycle == w[0].cycle + 1),
        "the records around step 1's start are not consecutive cycles: {:?}",
        around.iter().map(|r| r.cycle).collect::<Vec<_>>()
    );
    let goals: Vec<Option<u16>> = around.iter().map(|r| r.platform.map(|p| p.goal)).collect();
    println!(
        "{} goal writes, {} records; step 1 starts at cycle {}; platform goals around it {goals:?}",
        writes.len(),
        records.len(),
        records[k].cycle
    );
    assert_eq!(
        goals,
        [Some(2020), Some(2330), Some(2330), Some(2020)],
        "rest, then rise for the first two cycles of step 1, then rest"
    );
    // On the wire: exactly two goal writes at rise, one after the other (the lab's hold).
    let platform: Vec<i32> = writes.iter().map(|w| w.1[JOINTS].1).collect();
    let rises: Vec<usize> = (0..platform.len())
        .filter(|&k| platform[k] == 2330)
        .collect();
    assert_eq!(rises.len(), 2, "two cycles at rise: {rises:?}");
    assert_eq!(
        rises[1],
        rises[0] + 1,
        "the two cycles follow each other: {rises:?}"
    );
    assert!(
        platform.iter().all(|&g| g == 2330 || g == 2020),
        "{platform:?}"
    );
    Ok(())
}

#[test]
fn a_platform_servo_that_does_not_answer_refuses_play_naming_its_id() -> Result<()> {
    let test = "platform_silent";
    // Only the joints' servos on the bus: nobody answers at ID 23.
    let Some((board, mut link)) = start_with_servos(test, HIL_BUS, JOINTS, 1_000_000)? else {
        return Ok(());
    };
    let Some(emu) = board.emulator() else {
        return hil_tests::target::skip(test, "the bus trace needs the emulator");
    };
    let p = prepare(&mut link, 0)?;
    assert_eq!(p.state, PlatformState::NotAnswering);
    emu.bus_trace_start()?;
    let play = Request::Play(PlayCommand {
        slot: 0,
        direction: Direction::Forward,
        period_scale: 1000,
        steps: Steps::Count(2),
    });
    // The first Play selects the gait, whose new joint map sends the board to Boot to find its
    // servos (refused with WrongState, as `hil_tests::drive::start_playing` knows); once they
    // are found, Play meets the platform.
    let mut error = None;
    for _ in 0..50 {
        let seq = link.send(&play)?;
        let e = loop {
            match link.next_message(T)? {
                Some(DeviceMessage::Reply { seq: got, response }) if got == seq => match response {
                    Response::Error(e) => break e,
                    other => bail!("Play answered {other:?}"),
                },
                Some(_) => {}
                None => bail!("no answer to Play"),
            }
        };
        if !matches!(e, ProtocolError::WrongState { .. }) {
            error = Some(e);
            break;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    let error = error.context("Play refused with WrongState for 5 s (wall)")?;
    assert_eq!(
        error,
        ProtocolError::Platform(PlatformError::NotAnswering {
            servo_id: PLATFORM_ID
        })
    );
    assert_eq!(
        error.to_string(),
        "perturbation platform: platform servo ID 23 does not answer (ping, profile velocity or \
         position read failed): check its cable and ID"
    );
    // Nothing moves: ten cycles later no goal has been written.
    emu.run_for(Duration::from_millis(100))?;
    let writes = goal_writes(&emu.bus_trace_stop_bytes()?)?;
    assert!(
        writes.is_empty(),
        "goals written after the refusal: {writes:?}"
    );
    Ok(())
}

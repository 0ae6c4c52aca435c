//! Faults of docs/reliability.md that need the real firmware image and the emulator's controls
//! and are not covered by the other HIL tests: the USB link unplugged and plugged back while
//! walking, and a chip reset while walking. (Overload, a silent host, bad frames: tests/integration/safety.rs;
//! reset during an upload: tests/integration/link.rs; the soak: tests/integration/soak.rs.)

use anyhow::{Context, Result, ensure};
use hil_tests::drive::{T, start_playing, start_with_servos, upload_sine_gait};
use hil_tests::gait::{JOINTS, crc32};
use hil_tests::link::Link;
use hil_tests::{Emulator, Target};
use protocol::message::{Direction, RunState, Status, Steps};
use protocol::{Request, Response};
use std::time::Duration;

const HIL_BUS: &str = env!("CARGO_BIN_EXE_hil-bus");

/// The emulated board walking the sine gait continuously, and the upload's CRC; `None` when the
/// test is skipped (on a real board: `needs` says why it needs the emulator).
fn walking(test: &str, needs: &str) -> Result<Option<(Target, Link, u32)>> {
    let Some((board, mut link)) = start_with_servos(test, HIL_BUS, JOINTS, 1_000_000)? else {
        return Ok(None);
    };
    if board.emulator().is_none() {
        hil_tests::target::skip(test, needs)?;
        return Ok(None);
    }
    let crc = crc32(&upload_sine_gait(&mut link, "faults", None)?);
    start_playing(&mut link, 0, Direction::Forward, Steps::Continuous)?;
    Ok(Some((board, link, crc)))
}

/// Drops `link`, cuts the board's USB with `cut` (a re-plug, a chip reset), waits until the host
/// has it configured again and opens a new link.
fn reconnect(board: &Target, link: Link, cut: impl Fn(&Emulator) -> Result<()>) -> Result<Link> {
    let emu = board.emulator().context("emulator")?;
    let before = emu.events("usb_configured").len();
    drop(link);
    cut(emu)?;
    emu.wait_event_n("usb_configured", before + 1, Duration::from_secs(30))?;
    Link::open(board.port())
}

#[test]
fn usb_unplugged_and_back_while_walking_the_gait_goes_on() -> Result<()> {
    let Some((board, link, _)) =
        walking("usb_replug_walking", "re-plugging USB needs the emulator")?
    else {
        return Ok(());
    };
    let emu = board.emulator().context("emulator")?;
    emu.run_for(Duration::from_millis(500))?;
    let mut link = reconnect(&board, link, Emulator::usb_replug)?;
    let t0 = emu.sim_time()?;
    emu.run_for(Duration::from_secs(1))?;
    let s: Status = link.request(&Request::GetStatus, T)?;
    ensure!(
        s.state == RunState::Walking && s.fault.is_none(),
        "after the re-plug: {s:?}"
    );
    // The bus loop ran on through the re-plug: 100 Hz over the simulated time since.
    let elapsed = emu.sim_time()? - t0;
    ensure!(elapsed >= Duration::from_secs(1), "{elapsed:?}");
    Ok(())
}

#[test]
fn a_reset_while_walking_comes_up_idle_with_the_gait_kept() -> Result<()> {
    let Some((board, link, crc)) =
        walking("reset_walking", "resetting the chip needs the emulator")?
    else {
        return Ok(());
    };
    let emu = board.emulator().context("emulator")?;
    emu.run_for(Duration::from_millis(700))?;
    let mut link = link;
    let stored = slot0(&mut link)?;
    ensure!(
        stored.is_some(),
        "slot 0 holds the upload (Committed CRC {crc:#x})"
    );
    let mut link = reconnect(&board, link, Emulator::reset)?;
    // Nothing moves on its own after a reset.
    emu.run_for(Duration::from_millis(500))?;
    let s: Status = link.request(&Request::GetStatus, T)?;
    ensure!(
        s.state == RunState::Idle && s.playback.is_none(),
        "after the reset: {s:?}"
    );
    let kept = slot0(&mut link)?;
    ensure!(
        kept == stored,
        "slot 0 after the reset: {kept:?}, before {stored:?}"
    );
    start_playing(&mut link, 0, Direction::Forward, Steps::Count(1))?;
    Ok(())
}

/// The table CRC listed for slot 0 (the table's own stored CRC).
fn slot0(link: &mut Link) -> Result<Option<u32>> {
    let r: Response = link.request(&Request::ListGaits, T)?;
    let Response::Slots(slots) = r else {
        anyhow::bail!("ListGaits: {r:?}");
    };
    Ok(slots
        .iter()
        .find(|s| s.slot == 0)
        .and_then(|s| s.gait.map(|g| g.crc)))
}

//! Driving the board like `dbot` does, for the walking tests: start it with the virtual servo chain,
//! upload and select a gait, play a number of steps and collect telemetry until it stands again.

use crate::gait::{crc32, sine_gait, upload};
use crate::link::Link;
use crate::{Options, Target};
use anyhow::{Result, bail, ensure};
use protocol::message::{Direction, PlayCommand, RunState, Status, Steps};
use protocol::{DeviceMessage, MAX_CHUNK_LEN, Request, Response, Telemetry};
use std::time::Duration;

/// Wall-clock bound per request.
pub const T: Duration = Duration::from_secs(10);

/// The bus of [`Options`]: the servo chain program `hil_bus` with `servos` virtual servos (IDs
/// 1..=servos) at `baud`.
pub fn servo_bus(hil_bus: &str, servos: usize, baud: u32) -> Vec<String> {
    vec![
        hil_bus.into(),
        "--servos".into(),
        servos.to_string(),
        "--baud".into(),
        baud.to_string(),
    ]
}

/// The board started with `opts`, connected and past boot (`None`: the test is skipped).
pub fn start(test: &str, opts: Options) -> Result<Option<(Target, Link)>> {
    let Some(board) = Target::start(test, opts)? else {
        return Ok(None);
    };
    board.wait_for_log("host connected", Duration::from_secs(5))?;
    let link = Link::open(board.port())?;
    Ok(Some((board, link)))
}

/// The board with `servos` virtual servos (IDs 1..=servos) on its bus at `baud`, connected and
/// past boot; `hil_bus` is the servo chain program, `env!("CARGO_BIN_EXE_hil-bus")` in a test.
/// On a real board the servos are whatever is wired.
pub fn start_with_servos(
    test: &str,
    hil_bus: &str,
    servos: usize,
    baud: u32,
) -> Result<Option<(Target, Link)>> {
    let opts = Options {
        bus: Some(servo_bus(hil_bus, servos, baud)),
        ..Options::default()
    };
    start(test, opts)
}

/// Uploads the sine gait `name` (40 slices, 0.2 rad, [`sine_gait`]) into slot 0 and, with
/// `telemetry_every`, sets telemetry to every that many cycles (0: off). The table's bytes.
pub fn upload_sine_gait(
    link: &mut Link,
    name: &str,
    telemetry_every: Option<u16>,
) -> Result<Vec<u8>> {
    let (builder, table) = sine_gait(name, 40, 0.2)?;
    let r = upload(link, 0, &builder, &table, MAX_CHUNK_LEN, T)?;
    ensure!(
        r == Response::Committed {
            slot: 0,
            crc: crc32(&table)
        },
        "upload of {name}: {r:?}"
    );
    if let Some(every) = telemetry_every {
        let r: Response = link.request(&Request::SetTelemetry { every }, T)?;
        ensure!(r == Response::Ack, "SetTelemetry answered {r:?}");
    }
    Ok(table)
}

/// The telemetry records among `msgs`.
pub fn telemetry(msgs: &[DeviceMessage]) -> Vec<Telemetry> {
    msgs.iter()
        .filter_map(|m| match m {
            DeviceMessage::Telemetry(t) => Some(t.clone()),
            _ => None,
        })
        .collect()
}

/// Sends `Play`. Selecting a slot sends the board to Boot to find the table's servos; it refuses
/// `Play` until they are all known and the host plays again (firmware/src/controller/commands.rs).
pub fn start_playing(link: &mut Link, slot: u8, direction: Direction, steps: Steps) -> Result<()> {
    let play = Request::Play(PlayCommand {
        slot,
        direction,
        period_scale: 1000,
        steps,
    });
    for _ in 0..50 {
        let seq = link.send(&play)?;
        match link.reply::<Response>(seq, T) {
            Ok(Response::Ack) => return Ok(()),
            Ok(other) => bail!("Play answered {other:?}"),
            Err(e) if format!("{e:#}").contains("WrongState") => {
                std::thread::sleep(Duration::from_millis(100));
            }
            Err(e) => return Err(e),
        }
    }
    // Say what the board was doing, so that a refusal can be told from a slow machine.
    let status = link
        .request::<Status>(&Request::GetStatus, T)
        .map_or_else(|e| format!("GetStatus failed: {e:#}"), |s| format!("{s:?}"));
    bail!("the board refused Play for 5 s (wall) with WrongState; its status then: {status}")
}

/// Collects telemetry into `out` for 100 ms (wall), then asks for the status, keeping the telemetry
/// that arrived before its reply too; a fault is an error. The status.
pub fn poll_walking(link: &mut Link, out: &mut Vec<Telemetry>) -> Result<Status> {
    out.extend(telemetry(&link.collect(Duration::from_millis(100))?));
    let s: Status = link.request(&Request::GetStatus, T)?;
    out.extend(telemetry(&link.unsolicited.drain(..).collect::<Vec<_>>()));
    ensure!(s.fault.is_none(), "fault while walking: {s:?}");
    Ok(s)
}

/// Plays `steps` steps and collects telemetry until the board stands again.
pub fn play_steps(
    link: &mut Link,
    slot: u8,
    direction: Direction,
    steps: u32,
) -> Result<Vec<Telemetry>> {
    start_playing(link, slot, direction, Steps::Count(steps))?;
    let mut out = Vec::new();
    let mut walked = false;
    for _ in 0..600 {
        let s = poll_walking(link, &mut out)?;
        walked |= matches!(s.state, RunState::Walking | RunState::Stopping);
        if walked && s.state == RunState::Standing {
            // The last cycles' records may still be on their way.
            out.extend(telemetry(&link.collect(Duration::from_millis(300))?));
            return Ok(out);
        }
    }
    bail!("the board was still walking after 60 s (wall)")
}

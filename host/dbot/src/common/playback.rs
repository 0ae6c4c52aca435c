//! Starting and stopping playback, shared by `run` and `record --play`.

use anyhow::bail;
use board::link::{Board, LinkError, Transport};
use protocol::{Direction, GaitSummary, PlayCommand, ProtocolError, Steps};

use crate::common::gait_summary::describe;
use crate::common::session::Session;
use crate::common::words::direction_name;

/// What is about to be played, in one line: the slot, the gait stored there (name, size, period,
/// duty, CRC), and how it will be played.
pub fn announce(slot: u8, gait: &GaitSummary, command: &PlayCommand) -> String {
    let planned = f64::from(gait.header.step_period_us) * 1e-6;
    let period = planned * f64::from(command.period_scale) / 1000.0;
    let steps = match command.steps {
        Steps::Count(1) => "1 step".to_owned(),
        Steps::Count(k) => format!("{k} steps"),
        Steps::Continuous => "steps until stopped".to_owned(),
    };
    format!(
        "slot {slot}: {}; playing {steps} {} at {period:.3} s per step",
        describe(gait),
        direction_name(command.direction),
    )
}

/// The play command for `slot` and the gait stored there: the period (s) becomes a scale of the
/// slot's planned period.
pub fn play_command(
    s: &mut Session,
    slot: u8,
    steps: Option<u32>,
    period: Option<f64>,
    backward: bool,
) -> anyhow::Result<(PlayCommand, GaitSummary)> {
    let gaits = s.board.gaits()?;
    let Some(gait) = gaits.iter().find(|g| g.slot == slot).and_then(|g| g.gait) else {
        bail!(
            "slot {slot} is empty (the board has slots 0..{}); upload a table first",
            gaits.len()
        );
    };
    let planned = f64::from(gait.header.step_period_us) * 1e-6;
    let period_scale = match period {
        None => protocol::units::PERIOD_SCALE_ONE,
        Some(p) => {
            let scale = (p / planned * 1000.0).round();
            if !(p.is_finite() && (100.0..=10_000.0).contains(&scale)) {
                bail!(
                    "--period {p} s: the planned step is {planned:.3} s and the board plays 0.1 to 10 times it"
                );
            }
            scale as u16
        }
    };
    if steps == Some(0) {
        bail!("--steps 0: give at least one step");
    }
    let command = PlayCommand {
        slot,
        direction: if backward {
            Direction::Backward
        } else {
            Direction::Forward
        },
        period_scale,
        steps: steps.map_or(Steps::Continuous, Steps::Count),
    };
    Ok((command, gait))
}

/// Asks the board to stop walking at the end of the step. A board that refuses because it is not
/// walking (booting, in a fault) has nothing to stop.
pub fn stop_walk<T: Transport>(board: &mut Board<T>) -> anyhow::Result<()> {
    match board.stop() {
        Ok(())
        | Err(LinkError::Device {
            error: ProtocolError::WrongState { .. },
            ..
        }) => Ok(()),
        Err(e) => Err(anyhow::Error::new(e).context("stopping the walk after Ctrl-C")),
    }
}

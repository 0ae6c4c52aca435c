//! Starting playback, shared by `dbot run`, `dbot record --play` and `Board.record_trial`: the
//! step table to put into a slot first, the play command for a slot and its announcement.

use std::path::Path;

use board::link::{Board, LinkError, Transport};
use board::slot_health::{self, describe};
use protocol::{Direction, GaitSummary, PlayCommand, SlotInfo, Steps};

use crate::error::{Context, LabError, Result};

/// A slot about to be played: the gait it holds and what it lost, if anything.
#[derive(Debug, Clone, Copy)]
pub struct Stored {
    pub gait: GaitSummary,
    pub info: SlotInfo,
}

/// What is about to be played, in one line: the slot, the gait stored there (name, size, period,
/// duty, CRC), and how it will be played; then, for a slot that fell back to an older gait, which
/// newer gait was lost and why (on its own line, so it is not missed).
pub fn announce(slot: u8, stored: &Stored, command: &PlayCommand) -> String {
    let gait = &stored.gait;
    let planned = f64::from(gait.header.step_period_us) * 1e-6;
    let period = planned * f64::from(command.period_scale) / 1000.0;
    let steps = match command.steps {
        Steps::Count(1) => "1 step".to_owned(),
        Steps::Count(k) => format!("{k} steps"),
        Steps::Continuous => "steps until stopped".to_owned(),
    };
    let line = format!(
        "slot {slot}: {}; playing {steps} {} at {period:.3} s per step",
        describe(gait),
        command.direction.name(),
    );
    match slot_health::loss(&stored.info) {
        Some(loss) => format!("{line}\nWARNING slot {slot}: {loss}"),
        None => line,
    }
}

/// The play command for `slot` and the gait stored there: the period (s) becomes a scale of the
/// slot's planned period.
pub fn play_command<T: Transport>(
    board: &mut Board<T>,
    slot: u8,
    steps: Option<u32>,
    period: Option<f64>,
    backward: bool,
) -> Result<(PlayCommand, Stored)> {
    let gaits = board.gaits()?;
    let info = gaits.iter().find(|g| g.slot == slot).copied();
    let Some((gait, info)) = info.and_then(|i| Some((i.gait?, i))) else {
        if let Some(loss) = info.as_ref().and_then(slot_health::loss) {
            crate::bail!("slot {slot} holds no readable gait: {loss}; upload a table again");
        }
        crate::bail!("{}", slot_health::no_gait_in(slot, gaits.len()));
    };
    let planned = f64::from(gait.header.step_period_us) * 1e-6;
    let period_scale = match period {
        None => protocol::units::PERIOD_SCALE_ONE,
        Some(p) => match protocol::units::to_fixed(p / planned, 1000.0, 100, 10_000) {
            Some(scale) => scale as u16,
            None => crate::bail!(
                "period {p} s: the planned step is {planned:.3} s and the board plays 0.1 to 10 times it"
            ),
        },
    };
    if steps == Some(0) {
        crate::bail!("steps 0: give at least one step");
    }
    let command = PlayCommand::new(
        slot,
        Direction::backward_if(backward),
        period_scale,
        steps.map_or(Steps::Continuous, Steps::Count),
    );
    Ok((command, Stored { gait, info }))
}

/// Puts the step table `bytes` (read from `path`) into `slot` before a walk, unless the slot
/// holds that very table (same CRC, so a board's flash is not rewritten for nothing): the way a
/// lab walks its own gait on a robot that each command opens afresh (`--port physics`,
/// `--port virtual`). The table is checked by the rules as `dbot upload --table` checks it
/// (`board::rules::build::table_bytes`, its joints named by `model`, with `overrides`), held or
/// not, and the upload is the board library's; `stop` returning true abandons it (the slot keeps
/// its previous table). Returns the line to show for an upload (`None` when the slot held the
/// table already) and the warning of an override.
pub fn upload_table<T: Transport>(
    board: &mut Board<T>,
    slot: u8,
    path: &Path,
    bytes: &[u8],
    model: &planner::model::Model,
    overrides: board::rules::Overrides,
    stop: impl FnMut() -> bool,
) -> Result<(Option<String>, Option<board::rules::Overridden>)> {
    let checked = board::rules::build::table_bytes(
        bytes.to_vec(),
        &format!("step table {}", path.display()),
        model,
        overrides,
    )?;
    let warning = checked.warning().cloned();
    let table = protocol::GaitTable::parse(bytes)
        .with_context(|| format!("table {} is not a step table", path.display()))?;
    let held = board
        .gaits()?
        .iter()
        .find(|g| g.slot == slot)
        .and_then(|g| g.gait)
        .is_some_and(|g| g.crc == table.crc());
    if held {
        return Ok((None, warning));
    }
    let report = board.upload_unless(slot, &checked, |_, _| {}, stop);
    if let Err(e @ LinkError::UploadInterrupted { .. }) = report {
        return Err(LabError::Interrupted(format!("interrupted: {e}")));
    }
    let report =
        report.with_context(|| format!("uploading table {} into slot {slot}", path.display()))?;
    Ok((
        Some(format!(
            "slot {slot}: uploaded {} from {} (verified: CRC {:#010x})",
            describe(&report.stored),
            path.display(),
            report.stored.crc
        )),
        warning,
    ))
}

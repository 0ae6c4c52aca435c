//! The walk `dbot demo` and `dbot paper-robot` both record on a (physics or virtual) robot: the
//! gait in slot 0 played for a number of steps in a direction, its telemetry captured until the
//! robot stands again or an interrupt is requested.

use std::path::Path;

use anyhow::Context;
use board::link::{Board, Transport};
use board::record::{Ended, JointMeta, Recorder, Until, capture_while};
use protocol::{Direction, PlayCommand, Steps};

use crate::common::interrupt;

/// Plays slot 0 for `steps` steps in `direction` at its planned period and records the walk into
/// `csv` (telemetry queued before the start is dropped); how the capture ended says whether it
/// was interrupted.
pub fn play_and_record<T: Transport>(
    board: &mut Board<T>,
    direction: Direction,
    steps: u32,
    csv: &Path,
    joints: Vec<JointMeta>,
) -> anyhow::Result<(Recorder, Ended)> {
    board.discard_telemetry();
    board.play(PlayCommand {
        slot: 0,
        direction,
        period_scale: protocol::units::PERIOD_SCALE_ONE,
        steps: Steps::Count(steps),
    })?;
    let mut rec =
        Recorder::create(csv, joints).with_context(|| format!("creating {}", csv.display()))?;
    let ended = capture_while(
        board,
        &mut rec,
        Until {
            seconds: None,
            standing: true,
        },
        interrupt::requested,
        |_| {},
    )?;
    Ok((rec, ended))
}

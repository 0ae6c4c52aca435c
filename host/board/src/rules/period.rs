//! Playing a table faster than planned (`dbot run --period`, Python `Board.play(period_scale=)`,
//! and a gait queued after it: `dbot run --then`, `Board.queue_gait(period_scale=)`):
//! the table's angles and torques at the scaled period are checked against the same servo limits
//! as at build time (no-load speed, torque-speed line). Slower than planned needs no check: every
//! speed falls and the torque the servo gives at that speed grows, and the table's torques and
//! inverse-kinematics steps do not change with the period, so a table is at least as feasible as
//! it was when built (and checked, or overridden).

use std::path::Path;

use planner::model::Model;
use planner::plan::feasibility::{Feasibility, Servo, ServoLimits, Violation, check_servos};
use protocol::{GaitTable, PlayCommand, QueueCommand};

use super::{Overridden, Overrides, RuleError, Violations};
use crate::link::{Board, Transport};

/// The feasibility of `table` played at `scale` times its planned period; `names` name the table's
/// joints (board order).
pub fn table_feasibility(table: &GaitTable<'_>, names: &[String], scale: f64) -> Feasibility {
    let joints = table.joint_count();
    let servos: Vec<Servo<'_>> = (0..joints)
        .map(|j| Servo {
            column: j,
            joint: names.get(j).map_or("?", String::as_str),
            limits: table.joint(j).map(|m| ServoLimits::of(m.model)),
        })
        .collect();
    let column = |per: f64, value: &dyn Fn(usize, usize) -> Option<i16>| {
        (0..table.slice_count())
            .map(|s| {
                (0..joints)
                    .map(|j| value(s, j).map_or(0.0, |v| f64::from(v) / per))
                    .collect()
            })
            .collect::<Vec<Vec<f64>>>()
    };
    let q = column(protocol::units::ANGLE_PER_RAD, &|s, j| table.angle(s, j));
    let torque = column(protocol::units::TORQUE_PER_NM, &|s, j| table.torque(s, j));
    let header = table.header();
    let dt = f64::from(header.step_period_us) * 1e-6 * scale / table.slice_count() as f64;
    check_servos(&servos, &q, Some(&torque), dt)
}

/// Refuses playing `table` (in `slot`) at `scale` times its planned period when a servo could not
/// follow it there (speed over the no-load speed, torque over the torque-speed line), unless
/// overridden; nothing to check at `scale >= 1`.
pub fn check_scaled(
    table: &GaitTable<'_>,
    names: &[String],
    slot: u8,
    scale: f64,
    overrides: Overrides,
) -> Result<Option<Overridden>, RuleError> {
    if scale >= 1.0 {
        return Ok(None);
    }
    let f = table_feasibility(table, names, scale);
    let violations: Vec<Violation> = f
        .violations
        .into_iter()
        .filter(|v| match v {
            Violation::Speed { .. } | Violation::TorqueAtSpeed { .. } => true,
            // Neither changes with the period: the build's check (or its override) stands.
            Violation::Torque { .. } | Violation::Jump { .. } => false,
        })
        .collect();
    if violations.is_empty() {
        return Ok(None);
    }
    let planned_s = f64::from(table.header().step_period_us) * 1e-6;
    let what = format!("slot {slot} ({})", gait_name(table));
    let violations = Violations(violations);
    if overrides.allow_infeasible {
        return Ok(Some(Overridden::Infeasible { what, violations }));
    }
    Err(RuleError::TooFast {
        what,
        scale,
        period_s: planned_s * scale,
        planned_s,
        violations,
    })
}

/// A play command that passed the period rule ([`check_play`], the one maker of it): what
/// [`Board::play`] takes, with the warning of the override that let it through.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckedPlay {
    command: PlayCommand,
    warning: Option<Overridden>,
}

impl CheckedPlay {
    pub fn command(&self) -> &PlayCommand {
        &self.command
    }

    /// What `Overrides::allow_infeasible` let through, to show before the walk starts.
    pub fn warning(&self) -> Option<&Overridden> {
        self.warning.as_ref()
    }
}

/// A queued gait that passed the period rule ([`check_queue`], the one maker of it): what
/// [`Board::queue_gait`] takes.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckedQueue {
    command: QueueCommand,
    warning: Option<Overridden>,
}

impl CheckedQueue {
    pub fn command(&self) -> &QueueCommand {
        &self.command
    }

    /// What `Overrides::allow_infeasible` let through, to show before it plays.
    pub fn warning(&self) -> Option<&Overridden> {
        self.warning.as_ref()
    }
}

/// Checks `command` before it is played: at a period shorter than planned, the table of its slot
/// must be `known` (bytes the host holds, with the CRC the board reports for the slot) and pass
/// [`check_scaled`], its joints named by `model`; a table the host does not hold is refused
/// unless overridden. An empty slot is left to the board to refuse.
pub fn check_play<T: Transport>(
    board: &mut Board<T>,
    command: PlayCommand,
    known: Option<&[u8]>,
    model: &Model,
    overrides: Overrides,
) -> Result<CheckedPlay, RuleError> {
    let warning = check_command(board, &command, known, model, overrides)?;
    Ok(CheckedPlay { command, warning })
}

/// [`check_play`] for a gait queued after the one playing (`dbot run --then`, Python
/// `Board.queue_gait`): the same rule at the queued gait's own period scale, so a queued gait
/// cannot be played faster than the first gait may.
pub fn check_queue<T: Transport>(
    board: &mut Board<T>,
    command: QueueCommand,
    known: Option<&[u8]>,
    model: &Model,
    overrides: Overrides,
) -> Result<CheckedQueue, RuleError> {
    let warning = check_command(board, &command.0, known, model, overrides)?;
    Ok(CheckedQueue { command, warning })
}

fn check_command<T: Transport>(
    board: &mut Board<T>,
    command: &PlayCommand,
    known: Option<&[u8]>,
    model: &Model,
    overrides: Overrides,
) -> Result<Option<Overridden>, RuleError> {
    let scale = f64::from(command.period_scale) / f64::from(protocol::units::PERIOD_SCALE_ONE);
    if scale >= 1.0 {
        return Ok(None);
    }
    let stored = board.gaits()?;
    check_slot(&stored, command.slot, known, model, scale, overrides)
}

/// The check of [`check_play`] for the table in `slot` at `scale` (< 1), given the board's list
/// of slots (`stored`, for the CRC of the table it holds there).
pub(super) fn check_slot(
    stored: &[protocol::SlotInfo],
    slot: u8,
    known: Option<&[u8]>,
    model: &Model,
    scale: f64,
    overrides: Overrides,
) -> Result<Option<Overridden>, RuleError> {
    let Some(stored) = stored.iter().find(|s| s.slot == slot).and_then(|s| s.gait) else {
        return Ok(None);
    };
    let table = known
        .and_then(|b| GaitTable::parse(b).ok())
        .filter(|t| t.crc() == stored.crc);
    match table {
        Some(t) => {
            let names = crate::record::joint_names(model, Some(&t), t.joint_count());
            check_scaled(&t, &names, slot, scale, overrides)
        }
        None if overrides.allow_infeasible => Ok(Some(Overridden::Unchecked {
            slot,
            scale,
            crc: stored.crc,
        })),
        None => Err(RuleError::UnknownTable {
            slot,
            scale,
            crc: stored.crc,
        }),
    }
}

/// [`check_play`], then plays `command`.
pub fn play<T: Transport>(
    board: &mut Board<T>,
    command: protocol::PlayCommand,
    known: Option<&[u8]>,
    model: &Model,
    overrides: Overrides,
) -> Result<Option<Overridden>, RuleError> {
    let checked = check_play(board, command, known, model, overrides)?;
    board.play(&checked)?;
    Ok(checked.warning)
}

/// [`check_queue`], then queues `command`.
pub fn queue<T: Transport>(
    board: &mut Board<T>,
    command: QueueCommand,
    known: Option<&[u8]>,
    model: &Model,
    overrides: Overrides,
) -> Result<Option<Overridden>, RuleError> {
    let checked = check_queue(board, command, known, model, overrides)?;
    board.queue_gait(&checked)?;
    Ok(checked.warning)
}

/// The table in `slot` as the host holds it without the board: in the flash image of a
/// `virtual:PATH` robot (`port`, as opened; read without taking the image's lock, which the open
/// robot holds), else none (a board does not send its tables back).
pub fn table_of_port(port: &str, slot: u8) -> Result<Option<Vec<u8>>, crate::robot::ImageError> {
    match crate::port::PortSpec::parse(port) {
        Ok(crate::port::PortSpec::Virtual { image: Some(path) }) => table_in_image(&path, slot),
        Ok(
            crate::port::PortSpec::Virtual { image: None }
            | crate::port::PortSpec::Serial(_)
            | crate::port::PortSpec::Physics { .. },
        )
        | Err(_) => Ok(None),
    }
}

fn table_in_image(path: &Path, slot: u8) -> Result<Option<Vec<u8>>, crate::robot::ImageError> {
    let flash = crate::robot::image::load(path)?;
    let store = firmware::store::GaitStore::mount(flash, crate::robot::SLOTS);
    Ok(store.table(slot).map(<[u8]>::to_vec))
}

/// A table's name as the user gave it (quoted), for messages.
fn gait_name(table: &GaitTable<'_>) -> String {
    let header = table.header();
    format!("\"{}\"", header.name_str().unwrap_or("(name not UTF-8)"))
}

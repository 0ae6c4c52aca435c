//! Steering faster than planned (`dbot steer --speed`, Python `Board.steer(speed=)`): the board
//! plays the family's blend at the period scale of the speed ([`protocol::steer::period_scale_of`],
//! `1 / speed`), so each of the family's tables (straight, left, right) is checked at that scale
//! by the rule of [`super::period`], with the same words and the same override.
//!
//! Checking the three tables is enough for every heading: slice by slice and joint by joint the
//! blend is a convex combination of the straight gait and one side gait, angles and torques alike
//! (`protocol::steer`), so its speed (a difference of angles) is the same combination of theirs;
//! and the (speed, torque) pairs a servo can give (`|w| <= w0`, `|tau| <= stall (1 - |w| / w0)`)
//! form a convex set, so a blend of two pairs inside it stays inside it. At the planned speed and
//! slower nothing is checked (see [`super::period`]).

use planner::model::Model;

use super::period::check_slot;
use super::{Overridden, Overrides, RuleError};
use crate::link::{Board, LinkError, Transport};

/// Checks steering at `speed` (1 = as planned) before it is commanded: faster than planned, every
/// table of the family this host set ([`Board::steer_family`]) must be held by the host
/// (`held(slot)`: the bytes it uploaded there, or a `virtual:PATH` robot's image, see
/// [`super::period::table_of_port`]; an image that cannot be read is refused with its error) and be followed by the servos at that speed. The first of
/// straight, left and right that is not is refused (or, overridden, is the warning). A speed
/// outside the board's range is refused with the protocol's words; a family this host did not
/// set cannot be checked: refused unless overridden.
pub fn check_steer<T: Transport>(
    board: &mut Board<T>,
    heading_rad: f64,
    speed: f64,
    held: &dyn Fn(u8) -> Result<Option<Vec<u8>>, crate::robot::ImageError>,
    model: &Model,
    overrides: Overrides,
) -> Result<CheckedSteer, RuleError> {
    let command = protocol::steer::command_of(heading_rad, speed).map_err(LinkError::Steer)?;
    let warning = check_speed(board, command, held, model, overrides)?;
    Ok(CheckedSteer { command, warning })
}

/// A descending command that passed the steering rule ([`check_steer`], the one maker of it):
/// what [`Board::steer`] takes.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckedSteer {
    command: protocol::SteerCommand,
    warning: Option<Overridden>,
}

impl CheckedSteer {
    pub fn command(&self) -> &protocol::SteerCommand {
        &self.command
    }

    /// What `Overrides::allow_infeasible` let through.
    pub fn warning(&self) -> Option<&Overridden> {
        self.warning.as_ref()
    }
}

fn check_speed<T: Transport>(
    board: &mut Board<T>,
    command: protocol::SteerCommand,
    held: &dyn Fn(u8) -> Result<Option<Vec<u8>>, crate::robot::ImageError>,
    model: &Model,
    overrides: Overrides,
) -> Result<Option<Overridden>, RuleError> {
    let scale_fixed =
        protocol::steer::period_scale_of(command.speed_permille).map_err(LinkError::Steer)?;
    let scale = f64::from(scale_fixed) / f64::from(protocol::units::PERIOD_SCALE_ONE);
    if scale >= 1.0 {
        return Ok(None);
    }
    let speed = f64::from(command.speed_permille) / 1000.0;
    let Some(family) = board.steer_family() else {
        if overrides.allow_infeasible {
            return Ok(Some(Overridden::SteerUnchecked { speed }));
        }
        return Err(RuleError::UnknownFamily { speed });
    };
    let stored = board.gaits()?;
    let mut seen = Vec::with_capacity(3);
    for slot in [family.straight, family.left, family.right] {
        if seen.contains(&slot) {
            continue;
        }
        seen.push(slot);
        let known = held(slot)?;
        let checked = check_slot(&stored, slot, known.as_deref(), model, scale, overrides);
        match checked {
            Ok(None) => {}
            Ok(Some(w)) => return Ok(Some(steered_warning(w, speed))),
            Err(e) => return Err(steered_error(e, speed)),
        }
    }
    Ok(None)
}

/// Steers with a command [`check_steer`] passed (the only way to make one), returning the
/// warning of what its override let through.
pub fn steer<T: Transport>(
    board: &mut Board<T>,
    checked: CheckedSteer,
) -> Result<Option<Overridden>, RuleError> {
    board.steer(&checked)?;
    Ok(checked.warning)
}

/// The period rule's refusal, saying that it is the steering speed that asks for the period.
fn steered_error(e: RuleError, speed: f64) -> RuleError {
    match e {
        RuleError::TooFast {
            what,
            scale,
            period_s,
            planned_s,
            violations,
        } => RuleError::TooFast {
            what: format!("steering at speed {speed}: {what}"),
            scale,
            period_s,
            planned_s,
            violations,
        },
        other => other,
    }
}

fn steered_warning(w: Overridden, speed: f64) -> Overridden {
    match w {
        Overridden::Infeasible { what, violations } => Overridden::Infeasible {
            what: format!("steering at speed {speed}: {what}"),
            violations,
        },
        other => other,
    }
}

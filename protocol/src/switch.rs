//! Which gait may follow which: the one rule for switching gaits at a step boundary without
//! standing still, shared by the host (checks before it sends `QueueGait`) and the firmware
//! (refuses `QueueGait` with the same [`SwitchError`]), as `upload.rs` is for uploads.
//!
//! The switch happens at a step boundary of the gait playing. There the playing gait's goal is its
//! slice 0, in either direction (a forward step ends on slice 0, a backward step too, since a
//! backward step runs from slice 0 through the slices in reverse back to slice 0), and the queued
//! gait starts from its own slice 0. So across the switch the goal of joint j moves by
//!
//! ```text
//! jump_j = | goal_queued(0, j) - goal_playing(0, j) |,   goal(s, j) = angle(s, j) + torque(s, j) / k_j
//! ```
//!
//! (the torque-biased goal with each table's own stiffness `k_j`, the bias following the new
//! table from its first slice), on top of the one bus cycle of ordinary motion of either table.
//! The rule, in this order:
//!
//! 1. the two tables drive the same servos, joint by joint ([`SwitchError::ServoMap`]);
//! 2. the same legs are on the ground at the boundary ([`SwitchError::Stance`]): a table's legs on
//!    the ground there are those in stance in its last slice or its first (a leg lifting off or
//!    touching down at the boundary is on the ground at that instant), whichever the direction;
//! 3. every `jump_j` is at most what the joint's servo turns in one bus cycle at its no-load speed
//!    ([`jump_bound`]: MX-28 55 rev/min = 5.760 rad/s, at 100 Hz 0.0576 rad), else
//!    [`SwitchError::JointJump`] names the joint, the jump and the bound.
//!
//! What the rule does not know: stiffness or limits the host changed at run time (the firmware's
//! bias then uses those, the rule the tables' own).

use core::fmt;

use crate::gait::GaitTable;

/// Table angle units (1e-4 rad) per rad, as an integer ([`crate::units::ANGLE_PER_RAD`]).
const UNITS_PER_RAD: i32 = crate::units::ANGLE_PER_RAD as i32;

/// Why a gait cannot follow the one playing (or the last one queued).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum SwitchError {
    /// Joint `joint` of the queued table drives another servo than the playing one's (or one
    /// table has fewer joints: `joint` is the first missing one).
    ServoMap { joint: u8 },
    /// The legs on the ground at the step boundary differ (bit i = leg i in LF LM LH RF RM RH).
    Stance { playing: u8, queued: u8 },
    /// Joint `joint`'s goal would move by `jump` (1e-4 rad) across the switch, more than its
    /// servo turns in one bus cycle at no load, `bound` (1e-4 rad).
    JointJump { joint: u8, jump: u32, bound: u32 },
    /// The board's queue holds `capacity` gaits already.
    QueueFull { capacity: u8 },
    /// Nothing is playing that a gait could follow (the board is not walking).
    NothingPlaying,
}

/// Writes `v` 1e-4 rad as rad with four decimals.
fn rad(f: &mut fmt::Formatter<'_>, v: u32) -> fmt::Result {
    write!(f, "{}.{:04} rad", v / 10_000, v % 10_000)
}

impl fmt::Display for SwitchError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::ServoMap { joint } => write!(
                f,
                "joint {joint} drives another servo (or is missing) in the queued gait"
            ),
            Self::Stance { playing, queued } => write!(
                f,
                "different legs on the ground at the step boundary: playing {playing:#08b}, \
                 queued {queued:#08b} (bits LF LM LH RF RM RH from bit 0)"
            ),
            Self::JointJump { joint, jump, bound } => {
                write!(f, "joint {joint} would jump ")?;
                rad(f, *jump)?;
                write!(
                    f,
                    " at the switch, more than its servo turns in one bus cycle ("
                )?;
                rad(f, *bound)?;
                write!(f, ")")
            }
            Self::QueueFull { capacity } => {
                write!(f, "the gait queue is full ({capacity} gaits)")
            }
            Self::NothingPlaying => write!(f, "no gait is playing that another could follow"),
        }
    }
}

impl core::error::Error for SwitchError {}

/// What the joint's servo turns in one bus cycle at `cycle_hz` at its no-load speed, 1e-4 rad
/// (rounded down).
pub fn jump_bound(model: crate::ServoModel, cycle_hz: u16) -> u32 {
    let per_s = model.no_load_speed_rad_s() * UNITS_PER_RAD as f32;
    (per_s / f32::from(cycle_hz.max(1))) as u32
}

/// The torque-biased goal of `joint` at slice 0 of `t`, 1e-4 rad.
fn boundary_goal(t: &GaitTable<'_>, joint: usize) -> Option<i64> {
    let s = t.slice(0)?.sample(joint)?;
    let k = i64::from(t.joint(joint)?.stiffness.max(1));
    let bias = i64::from(s.torque) * i64::from(UNITS_PER_RAD) / k;
    Some(i64::from(s.angle) + bias)
}

/// Legs on the ground at a step boundary of `t`: in stance in its last slice or its first.
pub fn boundary_ground(t: &GaitTable<'_>) -> u8 {
    let first = t.stance(0).unwrap_or(0);
    let last = t.stance(t.slice_count().saturating_sub(1)).unwrap_or(0);
    first | last
}

/// Whether `queued` may follow `playing` at a step boundary on a bus of `cycle_hz` (the
/// direction does not matter: both end and start a step on slice 0). See the module text.
pub fn check_switch(
    playing: &GaitTable<'_>,
    queued: &GaitTable<'_>,
    cycle_hz: u16,
) -> Result<(), SwitchError> {
    let joints = playing.joint_count().max(queued.joint_count());
    for j in 0..joints {
        let same = match (playing.joint(j), queued.joint(j)) {
            (Some(a), Some(b)) => a.servo_id == b.servo_id,
            (Some(_), None) | (None, Some(_)) | (None, None) => false,
        };
        if !same {
            return Err(SwitchError::ServoMap { joint: j as u8 });
        }
    }
    let (a, b) = (boundary_ground(playing), boundary_ground(queued));
    if a != b {
        return Err(SwitchError::Stance {
            playing: a,
            queued: b,
        });
    }
    for j in 0..joints {
        let (Some(from), Some(to), Some(map)) = (
            boundary_goal(playing, j),
            boundary_goal(queued, j),
            queued.joint(j),
        ) else {
            return Err(SwitchError::ServoMap { joint: j as u8 });
        };
        let jump = (to - from).unsigned_abs().min(u32::MAX.into()) as u32;
        let bound = jump_bound(map.model, cycle_hz);
        if jump > bound {
            return Err(SwitchError::JointJump {
                joint: j as u8,
                jump,
                bound,
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bound_is_the_no_load_speed_times_one_cycle() {
        // MX-28: 55 rev/min x 2 pi / 60 = 5.7596 rad/s; / 100 Hz = 0.057596 rad = 575.96e-4.
        assert_eq!(jump_bound(crate::ServoModel::Mx28, 100), 575);
        // MX-64: 63 rev/min = 6.5973 rad/s; / 50 Hz = 0.131947 rad.
        assert_eq!(jump_bound(crate::ServoModel::Mx64, 50), 1319);
    }
}

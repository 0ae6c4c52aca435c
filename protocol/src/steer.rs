//! Steering on the device: the descending command (a heading and a speed) over a family of three
//! gaits in slots (right turn, straight, left turn), blended slice by slice on the board. The one
//! rule for which gaits form a family and how a heading becomes a blend, shared by the host (checks
//! before it sends `SetSteerFamily`) and the firmware (refuses it with the same [`SteerError`]).
//!
//! A heading `h` (mrad, positive left) in `-range ..= range` is a signed blend
//! `s = h / range` in `-1 ..= 1`; the board plays, at every phase of the step,
//!
//! ```text
//! goal(s) = straight + s (left - straight)     s >= 0
//!         = straight + |s| (right - straight)  s < 0
//! ```
//!
//! joint by joint, angles and torques alike (the same stiffness in all three tables, so the biased
//! goal blends as the angle does). The blend changes only at a step boundary, where every table's
//! goal is its slice 0, and by at most 1 per boundary: with `B` the switch rule's bound (each side's
//! slice 0 within `B` of the straight gait's, [`crate::check_switch`]), the goal then moves across a
//! boundary by at most `|s2 - s1| B <= B`, the same bound a queued switch keeps (full left to full
//! right takes two steps, through straight).
//!
//! A family (checked in this order, each side gait against the straight one):
//! 1. the same number of slices ([`SteerError::Slices`]) and step period ([`SteerError::Period`]);
//! 2. the switch rule between them ([`SteerError::Switch`]: servo map, legs on the ground at the
//!    boundary, the joint jump at slice 0);
//! 3. the same legs in stance in every slice ([`SteerError::Phase`]): a blend of a leg on the ground
//!    and a leg in the air would be neither;
//! 4. the same stiffness per joint ([`SteerError::Stiffness`]).

use core::fmt;

use crate::gait::GaitTable;
use crate::switch::{SwitchError, check_switch};

/// Blend weight units per 1 (the playback's interpolation fraction).
pub const WEIGHT_ONE: i32 = 65_536;

/// The speed range of [`crate::SteerCommand::speed_permille`], 1e-3 of the planned speed: the
/// period scales `1e6 / speed` that `Play` accepts (100 ..= 10 000).
pub const SPEED_PERMILLE: core::ops::RangeInclusive<u16> = 100..=10_000;

/// The command for `heading_rad` (positive left) at `speed` (1 = as planned), in the message's
/// units, refused outside the speed range (the heading's range is the family's, on the board).
#[cfg(feature = "std")]
pub fn command_of(heading_rad: f64, speed: f64) -> Result<crate::SteerCommand, SteerError> {
    use crate::units::to_fixed;
    let heading = to_fixed(heading_rad, 1000.0, i16::MIN.into(), i16::MAX.into())
        .ok_or(SteerError::NotRepresentable)?;
    let speed = to_fixed(speed, 1000.0, 0, u16::MAX.into()).ok_or(SteerError::NotRepresentable)?;
    let speed_permille = speed as u16;
    period_scale_of(speed_permille)?;
    Ok(crate::SteerCommand {
        heading_mrad: heading as i16,
        speed_permille,
    })
}

/// The family of slots `straight`, `left`, `right` whose side gaits stand for `range_rad`.
#[cfg(feature = "std")]
pub fn family_of(
    straight: u8,
    left: u8,
    right: u8,
    range_rad: f64,
) -> Result<crate::SteerFamily, SteerError> {
    let range = crate::units::to_fixed(range_rad, 1000.0, 0, i16::MAX.into())
        .ok_or(SteerError::NotRepresentable)?;
    if range == 0 {
        return Err(SteerError::ZeroRange);
    }
    Ok(crate::SteerFamily {
        straight,
        left,
        right,
        range_mrad: range as u16,
    })
}

/// Which side gait a signed blend uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Side {
    Left,
    Right,
}

/// Why a family cannot be blended or a steer command not followed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum SteerError {
    /// The gait in `slot` has `slices` slices, the straight gait `straight`.
    Slices {
        slot: u8,
        slices: u16,
        straight: u16,
    },
    /// The gait in `slot` has a step period of `period_us`, the straight gait `straight_us`.
    Period {
        slot: u8,
        period_us: u32,
        straight_us: u32,
    },
    /// The gait in `slot` cannot follow the straight gait at a step boundary.
    Switch { slot: u8, error: SwitchError },
    /// In slice `slice` the gait in `slot` has other legs in stance (`stance`, bit i = leg i in
    /// LF LM LH RF RM RH) than the straight gait (`straight`).
    Phase {
        slot: u8,
        slice: u16,
        stance: u8,
        straight: u8,
    },
    /// Joint `joint` of the gait in `slot` has another stiffness than in the straight gait.
    Stiffness { slot: u8, joint: u8 },
    /// The family's heading range is 0.
    ZeroRange,
    /// The heading is outside the family's range `-range_mrad ..= range_mrad`.
    Heading { heading_mrad: i16, range_mrad: u16 },
    /// The speed is outside [`SPEED_PERMILLE`].
    Speed { speed_permille: u16 },
    /// No family was set (`SetSteerFamily`) since the board started.
    NoFamily,
    /// A steered walk is playing: stop it first (gaits cannot be queued or the family changed
    /// under it).
    Steering,
    /// A heading or range in rad that is not a finite number within +-32.767 rad (mrad in
    /// `i16`), or a speed that is not a finite number within 0 ..= 65.535.
    NotRepresentable,
}

impl fmt::Display for SteerError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Slices {
                slot,
                slices,
                straight,
            } => write!(
                f,
                "gait slot {slot} has {slices} slices, the straight gait {straight}"
            ),
            Self::Period {
                slot,
                period_us,
                straight_us,
            } => write!(
                f,
                "gait slot {slot} has a step period of {period_us} us, the straight gait \
                 {straight_us} us"
            ),
            Self::Switch { slot, error } => {
                write!(
                    f,
                    "gait slot {slot} cannot follow the straight gait: {error}"
                )
            }
            Self::Phase {
                slot,
                slice,
                stance,
                straight,
            } => write!(
                f,
                "gait slot {slot} has other legs in stance in slice {slice} ({stance:#08b}) \
                 than the straight gait ({straight:#08b}; bits LF LM LH RF RM RH from bit 0)"
            ),
            Self::Stiffness { slot, joint } => write!(
                f,
                "joint {joint} of gait slot {slot} has another stiffness than in the straight gait"
            ),
            Self::ZeroRange => write!(f, "the steering family's heading range is 0"),
            Self::Heading {
                heading_mrad,
                range_mrad,
            } => write!(
                f,
                "heading {heading_mrad} mrad is outside the family's range +-{range_mrad} mrad"
            ),
            Self::Speed { speed_permille } => write!(
                f,
                "speed {speed_permille} permille is outside {} ..= {}",
                SPEED_PERMILLE.start(),
                SPEED_PERMILLE.end()
            ),
            Self::NoFamily => write!(f, "no steering family is set (SetSteerFamily)"),
            Self::Steering => write!(f, "a steered walk is playing: stop it first"),
            Self::NotRepresentable => write!(
                f,
                "a heading or range must be a finite number of rad within +-32.767, a speed a \
                 finite number within 0.1 ..= 10"
            ),
        }
    }
}

impl core::error::Error for SteerError {}

/// Whether `side` (in `slot`) can be blended with `straight` on a bus of `cycle_hz` (module text).
pub fn check_side(
    straight: &GaitTable<'_>,
    side: &GaitTable<'_>,
    slot: u8,
    cycle_hz: u16,
) -> Result<(), SteerError> {
    let (a, b) = (straight.header(), side.header());
    if a.slice_count != b.slice_count {
        return Err(SteerError::Slices {
            slot,
            slices: b.slice_count,
            straight: a.slice_count,
        });
    }
    if a.step_period_us != b.step_period_us {
        return Err(SteerError::Period {
            slot,
            period_us: b.step_period_us,
            straight_us: a.step_period_us,
        });
    }
    check_switch(straight, side, cycle_hz).map_err(|error| SteerError::Switch { slot, error })?;
    for s in 0..straight.slice_count() {
        let (want, got) = (straight.stance(s), side.stance(s));
        if want != got {
            return Err(SteerError::Phase {
                slot,
                slice: s as u16,
                stance: got.unwrap_or(0),
                straight: want.unwrap_or(0),
            });
        }
    }
    for j in 0..straight.joint_count() {
        let k = |t: &GaitTable<'_>| t.joint(j).map(|m| m.stiffness);
        if k(straight) != k(side) {
            return Err(SteerError::Stiffness {
                slot,
                joint: j as u8,
            });
        }
    }
    Ok(())
}

/// The signed blend of `heading_mrad` in a family of `range_mrad`, [`WEIGHT_ONE`] = the side gait
/// fully (positive: left), refused outside the range.
pub fn blend_of(heading_mrad: i16, range_mrad: u16) -> Result<i32, SteerError> {
    if range_mrad == 0 {
        return Err(SteerError::ZeroRange);
    }
    if i32::from(heading_mrad).unsigned_abs() > u32::from(range_mrad) {
        return Err(SteerError::Heading {
            heading_mrad,
            range_mrad,
        });
    }
    let w = i64::from(heading_mrad) * i64::from(WEIGHT_ONE) / i64::from(range_mrad);
    Ok(w as i32)
}

/// The blend after a step boundary on the way from `now` to `target`: at most [`WEIGHT_ONE`] on.
pub fn blend_step(now: i32, target: i32) -> i32 {
    now + (target - now).clamp(-WEIGHT_ONE, WEIGHT_ONE)
}

/// The period scale (1e-3) of a speed (1e-3 of the planned speed), refused outside
/// [`SPEED_PERMILLE`].
pub fn period_scale_of(speed_permille: u16) -> Result<u16, SteerError> {
    if !SPEED_PERMILLE.contains(&speed_permille) {
        return Err(SteerError::Speed { speed_permille });
    }
    Ok(((1_000_000 + u32::from(speed_permille) / 2) / u32::from(speed_permille)) as u16)
}

/// Which side gait blend `w` plays, and how much of it (0 ..= [`WEIGHT_ONE`]).
pub fn side_of(w: i32) -> (Side, u32) {
    if w >= 0 {
        (Side::Left, w.unsigned_abs())
    } else {
        (Side::Right, w.unsigned_abs())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_heading_is_its_fraction_of_the_range() {
        // 150 of 300 mrad: half the left gait; -300: all of the right one; 100 of 300: 21845.33.
        assert_eq!(blend_of(150, 300), Ok(32_768));
        assert_eq!(blend_of(-300, 300), Ok(-65_536));
        assert_eq!(blend_of(100, 300), Ok(21_845));
        assert_eq!(
            blend_of(301, 300),
            Err(SteerError::Heading {
                heading_mrad: 301,
                range_mrad: 300
            })
        );
        assert_eq!(blend_of(0, 0), Err(SteerError::ZeroRange));
    }

    #[test]
    fn the_blend_moves_at_most_one_side_gait_per_boundary() {
        // Full left to full right: through straight, two boundaries.
        assert_eq!(blend_step(65_536, -65_536), 0);
        assert_eq!(blend_step(0, -65_536), -65_536);
        assert_eq!(blend_step(1000, 30_000), 30_000);
    }

    #[test]
    fn si_values_become_the_messages_units_or_a_refusal() {
        assert_eq!(
            command_of(-0.15, 0.5),
            Ok(crate::SteerCommand {
                heading_mrad: -150,
                speed_permille: 500
            })
        );
        assert_eq!(command_of(f64::NAN, 1.0), Err(SteerError::NotRepresentable));
        assert_eq!(command_of(40.0, 1.0), Err(SteerError::NotRepresentable));
        assert_eq!(
            command_of(0.0, 0.05),
            Err(SteerError::Speed { speed_permille: 50 })
        );
        assert_eq!(family_of(0, 1, 2, 0.0004), Err(SteerError::ZeroRange));
        assert_eq!(family_of(0, 1, 2, 0.3).map(|f| f.range_mrad), Ok(300));
    }

    #[test]
    fn speed_is_the_inverse_of_the_period_scale() {
        assert_eq!(period_scale_of(1000), Ok(1000));
        assert_eq!(period_scale_of(500), Ok(2000));
        // 1e6 / 1500 = 666.67, rounded to nearest.
        assert_eq!(period_scale_of(1500), Ok(667));
        assert_eq!(
            period_scale_of(99),
            Err(SteerError::Speed { speed_permille: 99 })
        );
    }
}

//! The servo stiffness a board can be given: the board's unit (mN m/rad, `protocol::limits`) and
//! what the servo's Position P Gain register can hold. The firmware writes the register value
//! nearest the stiffness (`dynamixel::units::p_gain_for_stiffness`, 1 ..= 16383) and the torque
//! bias divides by the stiffness itself, so a stiffness the register cannot hold would make the
//! bias divide by a stiffness the servo never has: it is refused, saying what the servo would get.

use dynamixel::ServoModel;
use dynamixel::units::{P_GAIN_MAX, p_gain_for_stiffness, stiffness_nm_per_rad};
use protocol::limits::{LimitError, stiffness_units};

use super::RuleError;
use crate::link::{Board, Transport};

/// Why a stiffness cannot be given to a servo.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum StiffnessError {
    /// Outside the board's unit range.
    #[error(transparent)]
    Limit(#[from] LimitError),
    /// More than P gain 16383 gives.
    #[error(
        "stiffness {stiffness} N m/rad is more than the {servo}'s Position P Gain register holds: at most {max:.1} N m/rad (P gain {P_GAIN_MAX}, estimate); the servo would get {max:.1} N m/rad while the torque bias divided by {stiffness}"
    )]
    AboveRegister {
        servo: ServoModel,
        stiffness: f64,
        max: f64,
    },
    /// Less than half of what P gain 1 gives.
    #[error(
        "stiffness {stiffness} N m/rad is less than the {servo}'s Position P Gain register can be set to: P gain 1 is {least:.4} N m/rad (estimate), and it rounds to 0 (a limp servo), so the servo would get {least:.4} N m/rad while the torque bias divided by {stiffness}; give at least {min:.4} N m/rad"
    )]
    BelowRegister {
        servo: ServoModel,
        stiffness: f64,
        least: f64,
        min: f64,
    },
}

/// The P gain `servo` gets for `stiffness` (N m/rad), refused when the register cannot hold it.
pub fn p_gain(servo: ServoModel, stiffness: f64) -> Result<u16, StiffnessError> {
    let unit = f64::from(servo.stiffness_per_p_gain());
    let nearest = (stiffness / unit).round();
    if nearest > f64::from(P_GAIN_MAX) {
        return Err(StiffnessError::AboveRegister {
            servo,
            stiffness,
            max: f64::from(stiffness_nm_per_rad(servo, P_GAIN_MAX)),
        });
    }
    if nearest < 1.0 {
        return Err(StiffnessError::BelowRegister {
            servo,
            stiffness,
            least: unit,
            min: unit / 2.0,
        });
    }
    Ok(p_gain_for_stiffness(servo, stiffness as f32))
}

/// The board's units (mN m/rad) for `stiffness` (N m/rad) when every servo model a joint may carry
/// holds it in its P gain register (the board does not say which servo drives which joint).
pub fn units(stiffness: f64) -> Result<u32, StiffnessError> {
    if stiffness == 0.0 {
        // The firmware's "no torque bias" (firmware/src/bias.rs): nothing is divided by it, and
        // the servos keep the P gain they have (the board writes no gain for a 0).
        return Ok(0);
    }
    let units = stiffness_units(stiffness)?;
    for servo in ServoModel::ALL {
        p_gain(servo, stiffness)?;
    }
    Ok(units)
}

/// A stiffness the rule passed ([`units`]): what [`Board::set_stiffness`] takes. Made only by
/// [`Stiffness::of`] (N m/rad), [`Stiffness::of_units`] (the board's unit, as a kept setting) and
/// [`Stiffness::OFF`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Stiffness(u32);

impl Stiffness {
    /// 0: the torque bias off, the servos keep their P gain.
    pub const OFF: Self = Self(0);

    /// `stiffness` N m/rad under [`units`]' rule.
    pub fn of(stiffness: f64) -> Result<Self, StiffnessError> {
        units(stiffness).map(Self)
    }

    /// A stiffness in the board's unit (mN m/rad, e.g. a setting kept beside a virtual robot),
    /// under the same rule.
    pub fn of_units(units: u32) -> Result<Self, StiffnessError> {
        Self::of(f64::from(units) / protocol::units::STIFFNESS_PER_NM_RAD)
    }

    /// In the board's unit, mN m/rad.
    pub fn units(self) -> u32 {
        self.0
    }
}

/// Sets the stiffness of `joint` (joint-map index) or, with `None`, of every joint of the board,
/// after [`units`] accepted it. Returns the joints set.
pub fn set_stiffness<T: Transport>(
    board: &mut Board<T>,
    joint: Option<u8>,
    stiffness: f64,
) -> Result<Vec<u8>, RuleError> {
    let units = Stiffness::of(stiffness).map_err(RuleError::Stiffness)?;
    let list: Vec<u8> = match joint {
        Some(j) => vec![j],
        None => (0..board.settings()?.joints.len() as u8).collect(),
    };
    if list.is_empty() {
        return Err(RuleError::NoJointMap);
    }
    for &j in &list {
        board
            .set_stiffness(j, units)
            .map_err(|source| RuleError::JointSetting { joint: j, source })?;
    }
    Ok(list)
}

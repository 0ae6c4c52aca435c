//! The per-joint map of a table: which servo drives the joint and how its angle maps to ticks.

use crate::units::{TICKS_PER_REV, angle_units_to_ticks, ticks_to_angle_units};

/// Servo model of a joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum ServoModel {
    /// Dynamixel MX-28 (protocol 2.0 firmware), 2.5 N m stall at 12 V.
    Mx28,
    /// Dynamixel MX-64 (protocol 2.0 firmware), 6.0 N m stall at 12 V.
    Mx64,
}

impl ServoModel {
    /// Code of the model in a table.
    pub fn code(self) -> u8 {
        match self {
            Self::Mx28 => 0,
            Self::Mx64 => 1,
        }
    }

    /// The model of a table code.
    pub fn from_code(code: u8) -> Option<Self> {
        match code {
            0 => Some(Self::Mx28),
            1 => Some(Self::Mx64),
            _ => None,
        }
    }
}

/// Whether servo ticks grow with the joint angle or against it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Sign {
    /// Ticks grow with the angle.
    Positive,
    /// Ticks shrink as the angle grows.
    Negative,
}

impl Sign {
    /// +1 or -1.
    pub fn as_i32(self) -> i32 {
        match self {
            Self::Positive => 1,
            Self::Negative => -1,
        }
    }
}

/// One joint of a table: its servo, the angle-to-tick map, limits and the stiffness used for the
/// torque bias.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct JointMap {
    /// Dynamixel ID (0 ..= 252).
    pub servo_id: u8,
    /// Servo model.
    pub model: ServoModel,
    /// Direction of the ticks.
    pub sign: Sign,
    /// Servo ticks at joint angle 0 (0 ..= 4095).
    pub zero_offset: u16,
    /// Lowest joint angle, 1e-4 rad.
    pub min: i16,
    /// Highest joint angle, 1e-4 rad.
    pub max: i16,
    /// Servo stiffness for the torque bias, mN m/rad (> 0).
    pub stiffness: u32,
}

impl JointMap {
    /// Goal ticks of a joint angle (1e-4 rad): `zero + sign * angle * 4096 / 2 pi`, rounded.
    ///
    /// Takes an `i32` so that a biased angle beyond the `i16` range still converts; clamp to the
    /// limits first.
    pub fn angle_to_ticks(&self, angle: i32) -> i32 {
        i32::from(self.zero_offset) + self.sign.as_i32() * angle_units_to_ticks(angle)
    }

    /// Joint angle (1e-4 rad) of a present position in ticks, wrapped to one turn around the zero
    /// (+-pi) so that it always fits an `i16`.
    pub fn ticks_to_angle(&self, ticks: i32) -> i16 {
        let half = TICKS_PER_REV / 2;
        let delta = (ticks.wrapping_sub(i32::from(self.zero_offset)) + half)
            .rem_euclid(TICKS_PER_REV)
            - half;
        ticks_to_angle_units(self.sign.as_i32() * delta) as i16
    }
}

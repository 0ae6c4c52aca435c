//! The per-joint map of a table: which servo drives the joint and how its angle maps to ticks.

use crate::calibration::Calibration;

/// The servo model of a joint: the bus crate's, one enum for table, bus and host.
pub use dynamixel::ServoModel;

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
    /// The leg the joint moves (0 ..= 5 in LF, LM, LH, RF, RM, RH), if the table gives it: the
    /// board's start ramp lifts a leg's joints together, a pair of legs at a time.
    pub leg: Option<u8>,
}

impl JointMap {
    /// The joint's angle <-> ticks calibration.
    pub fn calibration(&self) -> Calibration {
        Calibration::new(self.model, i32::from(self.zero_offset), self.sign)
    }

    /// Goal ticks of a joint angle (1e-4 rad): `zero + sign * angle * 4096 / 2 pi`, rounded
    /// ([`Calibration::angle_to_ticks`]).
    pub fn angle_to_ticks(&self, angle: i32) -> i32 {
        self.calibration().angle_to_ticks(angle)
    }

    /// Joint angle (1e-4 rad) of a present position in ticks, wrapped to one turn around the zero
    /// ([`Calibration::ticks_to_angle`]).
    pub fn ticks_to_angle(&self, ticks: i32) -> i16 {
        self.calibration().ticks_to_angle(ticks)
    }
}

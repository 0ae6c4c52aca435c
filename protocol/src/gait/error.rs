//! Why a byte string is not a valid gait table.

use core::fmt;

/// Field of a joint record that failed validation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum JointField {
    ServoId,
    Model,
    Sign,
    ZeroOffset,
    Limits,
    Stiffness,
    Reserved,
    /// Added after `Reserved`, so that the wire's codes of the others stay as they were.
    Leg,
}

impl JointField {
    /// The field as the step-table format (docs) names it.
    pub const fn name(self) -> &'static str {
        match self {
            JointField::ServoId => "servo ID",
            JointField::Model => "servo model",
            JointField::Sign => "sign",
            JointField::ZeroOffset => "zero offset",
            JointField::Limits => "limits",
            JointField::Stiffness => "stiffness",
            JointField::Leg => "leg",
            JointField::Reserved => "reserved byte",
        }
    }
}

/// A table failed validation; every variant names where.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum TableError {
    /// Fewer bytes than the header (or the declared length) needs.
    Truncated { len: u32, needed: u32 },
    /// The first four bytes are not "DBGT".
    BadMagic { found: [u8; 4] },
    /// A layout version this build does not read.
    UnsupportedVersion { found: u16, supported: u16 },
    /// Joint count 0 or above [`crate::MAX_JOINTS`].
    BadJointCount { count: u8 },
    /// Slice count 0 or above [`super::MAX_SLICES`].
    BadSliceCount { count: u16 },
    /// Duty factor not strictly between 0 and 1.
    BadDuty { duty: u16 },
    /// Step period of zero.
    BadPeriod,
    /// A reserved header byte is not zero.
    Reserved { offset: u8 },
    /// The declared total length disagrees with the counts.
    LengthMismatch { declared: u32, computed: u32 },
    /// The stored CRC does not match the contents.
    Crc { stored: u32, computed: u32 },
    /// A joint record is invalid.
    BadJoint { joint: u8, field: JointField },
    /// Stance bits beyond the six legs, or a non-zero reserved slice byte.
    BadStance { slice: u16, bits: u8 },
    /// A planned angle outside its joint's limits.
    AngleOutOfLimits { slice: u16, joint: u8, angle: i16 },
}

impl fmt::Display for TableError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::Truncated { len, needed } => write!(f, "table of {len} bytes, needs {needed}"),
            Self::BadMagic { found } => write!(f, "bad magic {found:02x?}, expected \"DBGT\""),
            Self::UnsupportedVersion { found, supported } => {
                write!(
                    f,
                    "table format version {found}, this build reads {supported}"
                )
            }
            Self::BadJointCount { count } => {
                write!(f, "joint count {count} outside 1..={}", crate::MAX_JOINTS)
            }
            Self::BadSliceCount { count } => {
                write!(f, "slice count {count} outside 1..={}", super::MAX_SLICES)
            }
            Self::BadDuty { duty } => write!(f, "duty {duty} (1e-4) outside 1..=9999"),
            Self::BadPeriod => write!(f, "step period is zero"),
            Self::Reserved { offset } => write!(f, "reserved header byte {offset} is not zero"),
            Self::LengthMismatch { declared, computed } => {
                write!(
                    f,
                    "header declares {declared} bytes, counts give {computed}"
                )
            }
            Self::Crc { stored, computed } => {
                write!(
                    f,
                    "table CRC {stored:#010x} does not match contents ({computed:#010x})"
                )
            }
            Self::BadJoint { joint, field } => write!(f, "joint {joint}: invalid {}", field.name()),
            Self::BadStance { slice, bits } => {
                write!(f, "slice {slice}: invalid stance byte {bits:#04x}")
            }
            Self::AngleOutOfLimits {
                slice,
                joint,
                angle,
            } => {
                write!(
                    f,
                    "slice {slice}, joint {joint}: angle {angle} outside the joint limits"
                )
            }
        }
    }
}

impl core::error::Error for TableError {}

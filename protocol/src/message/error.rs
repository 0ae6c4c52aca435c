//! Errors and faults that travel as data.

use core::fmt;

use super::RunState;
use crate::{FrameError, TableError, UploadError};

/// A run-time setting named in [`ProtocolError::InvalidSetting`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Setting {
    Baud,
    CycleRate,
    Stiffness,
    Limits,
    PeriodScale,
    StepCount,
    Telemetry,
    StreamTimeout,
    StreamFeedback,
    SetpointJoints,
}

/// Why a request failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum ProtocolError {
    /// The board does not implement this request.
    Unsupported,
    /// The request is not allowed in this state (e.g. `Play` while in a fault).
    WrongState { state: RunState },
    /// No slot with this number.
    NoSuchSlot { slot: u8, slots: u8 },
    /// The slot holds no table.
    SlotEmpty { slot: u8 },
    /// The slot is playing and cannot be replaced or deleted now.
    SlotBusy { slot: u8 },
    /// No joint with this index.
    NoSuchJoint { joint: u8, joints: u8 },
    /// A setting's value is out of its range.
    InvalidSetting { setting: Setting, value: i32 },
    /// An upload step was refused.
    Upload(UploadError),
    /// A stored or uploaded table is invalid.
    Table(TableError),
    /// The flash refused an erase or a write at this offset of the store.
    Flash { offset: u32 },
    /// A frame could not be decoded.
    Frame(FrameError),
}

impl fmt::Display for ProtocolError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Unsupported => write!(f, "request not supported by this firmware"),
            Self::WrongState { state } => write!(f, "not allowed in state {state:?}"),
            Self::NoSuchSlot { slot, slots } => {
                write!(f, "no gait slot {slot} (board has {slots})")
            }
            Self::SlotEmpty { slot } => write!(f, "gait slot {slot} is empty"),
            Self::SlotBusy { slot } => write!(f, "gait slot {slot} is playing"),
            Self::NoSuchJoint { joint, joints } => {
                write!(f, "no joint {joint} (board has {joints})")
            }
            Self::InvalidSetting { setting, value } => {
                write!(f, "{setting:?} = {value} out of range")
            }
            Self::Upload(e) => write!(f, "upload: {e}"),
            Self::Table(e) => write!(f, "gait table: {e}"),
            Self::Flash { offset } => write!(f, "flash error at store offset {offset:#x}"),
            Self::Frame(e) => write!(f, "frame: {e}"),
        }
    }
}

impl core::error::Error for ProtocolError {}

impl From<UploadError> for ProtocolError {
    fn from(e: UploadError) -> Self {
        Self::Upload(e)
    }
}

impl From<TableError> for ProtocolError {
    fn from(e: TableError) -> Self {
        Self::Table(e)
    }
}

/// What put the robot into the fault state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum FaultKind {
    /// The host sent `EmergencyStop`.
    EmergencyStop,
    /// A servo reported a hardware error (its Hardware Error Status bits).
    ServoError { bits: u8 },
    /// A servo missed this many bus cycles in a row.
    ServoMissing { cycles: u8 },
    /// No streaming setpoint for the configured number of cycles.
    SetpointTimeout,
    /// The watchdog reset the firmware.
    Watchdog,
}

/// A fault and the joint it concerns, if any.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Fault {
    pub kind: FaultKind,
    pub joint: Option<u8>,
}

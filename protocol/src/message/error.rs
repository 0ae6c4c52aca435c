//! Errors and faults that travel as data.

use core::fmt;

use super::RunState;
use crate::platform::PlatformError;
use crate::steer::SteerError;
use crate::switch::SwitchError;
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
    /// Heat and supply limits (appended: protocol version 8).
    HealthLimits,
    /// A servo read's ID or length (appended: protocol version 9).
    ServoRead,
}

impl Setting {
    /// The setting's name as `dbot set` and the usage guide spell it.
    pub const fn name(self) -> &'static str {
        match self {
            Setting::Baud => "baud",
            Setting::CycleRate => "cycle rate",
            Setting::Stiffness => "stiffness",
            Setting::Limits => "limits",
            Setting::PeriodScale => "period scale",
            Setting::StepCount => "step count",
            Setting::Telemetry => "telemetry",
            Setting::StreamTimeout => "stream timeout",
            Setting::StreamFeedback => "stream feedback",
            Setting::SetpointJoints => "setpoint joints",
            Setting::HealthLimits => "health limits",
            Setting::ServoRead => "servo read",
        }
    }
}

impl fmt::Display for Setting {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
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
    /// A queued gait cannot follow the one before it (appended: protocol version 5).
    Switch(SwitchError),
    /// A steering family or command was refused (appended: protocol version 6).
    Steer(SteerError),
    /// The perturbation platform was refused (appended: protocol version 7).
    Platform(PlatformError),
}

impl fmt::Display for ProtocolError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Unsupported => write!(f, "request not supported by this firmware"),
            Self::WrongState { state } => write!(f, "not allowed in state {state}"),
            Self::NoSuchSlot { slot, slots } => {
                write!(f, "no gait slot {slot} (board has {slots})")
            }
            Self::SlotEmpty { slot } => write!(f, "gait slot {slot} is empty"),
            Self::SlotBusy { slot } => write!(f, "gait slot {slot} is playing"),
            Self::NoSuchJoint { joint, joints } => {
                write!(f, "no joint {joint} (board has {joints})")
            }
            Self::InvalidSetting { setting, value } => {
                write!(f, "{setting} = {value} out of range")
            }
            Self::Upload(e) => write!(f, "upload: {e}"),
            Self::Table(e) => write!(f, "gait table: {e}"),
            Self::Flash { offset } => write!(f, "flash error at store offset {offset:#x}"),
            Self::Frame(e) => write!(f, "frame: {e}"),
            Self::Switch(e) => write!(f, "gait switch: {e}"),
            Self::Steer(e) => write!(f, "steering: {e}"),
            Self::Platform(e) => write!(f, "perturbation platform: {e}"),
        }
    }
}

impl core::error::Error for ProtocolError {}

impl From<UploadError> for ProtocolError {
    fn from(e: UploadError) -> Self {
        Self::Upload(e)
    }
}

impl From<SwitchError> for ProtocolError {
    fn from(e: SwitchError) -> Self {
        Self::Switch(e)
    }
}

impl From<SteerError> for ProtocolError {
    fn from(e: SteerError) -> Self {
        Self::Steer(e)
    }
}

impl From<PlatformError> for ProtocolError {
    fn from(e: PlatformError) -> Self {
        Self::Platform(e)
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
    /// A servo's output did not follow its goal: over one detection window the goal (and the
    /// planned angle) moved over `goal_range` ticks while the present position moved over only
    /// `present_range` ticks (a jammed gear, a blocked joint). Appended last, so the variants above
    /// keep their encoding; an older host cannot decode it, hence protocol version 2.
    ServoStuck { goal_range: u16, present_range: u16 },
}

impl FaultKind {
    /// The variant's name, as `dbot status` and the Python package show it (`"ServoStuck"`).
    pub fn name(&self) -> &'static str {
        match self {
            Self::EmergencyStop => "EmergencyStop",
            Self::ServoError { .. } => "ServoError",
            Self::ServoMissing { .. } => "ServoMissing",
            Self::SetpointTimeout => "SetpointTimeout",
            Self::Watchdog => "Watchdog",
            Self::ServoStuck { .. } => "ServoStuck",
        }
    }
}

impl fmt::Display for FaultKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::EmergencyStop => write!(f, "emergency stop by the host"),
            Self::ServoError { bits } => {
                write!(f, "servo hardware error (error bits {bits:#04x})")
            }
            Self::ServoMissing { cycles } => {
                write!(f, "servo missing: no usable reply for {cycles} bus cycles")
            }
            Self::SetpointTimeout => write!(f, "no streaming setpoint in time"),
            Self::Watchdog => write!(f, "the watchdog reset the firmware"),
            Self::ServoStuck {
                goal_range,
                present_range,
            } => write!(
                f,
                "servo stuck: its goal moved over {goal_range} ticks, its position over {present_range}"
            ),
        }
    }
}

impl fmt::Display for Fault {
    /// `ServoStuck on joint 2: servo stuck: ...`
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.joint {
            Some(j) => write!(f, "{} on joint {j}: {}", self.kind.name(), self.kind),
            None => write!(f, "{}: {}", self.kind.name(), self.kind),
        }
    }
}

/// A fault and the joint it concerns, if any.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Fault {
    pub kind: FaultKind,
    pub joint: Option<u8>,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// postcard encodes an enum as its variant index (varint) followed by the fields (u8 raw, u16
    /// as a LEB128 varint): bytes written out by hand from the postcard wire specification.
    #[test]
    fn a_fault_reads_with_its_name_joint_and_numbers() {
        let stuck = Fault {
            kind: FaultKind::ServoStuck {
                goal_range: 312,
                present_range: 1,
            },
            joint: Some(2),
        };
        let mut buf = [0u8; 128];
        let mut w = Writer(&mut buf, 0);
        core::fmt::write(&mut w, format_args!("{stuck}")).unwrap();
        let text = core::str::from_utf8(&w.0[..w.1]).unwrap();
        assert_eq!(
            text,
            "ServoStuck on joint 2: servo stuck: its goal moved over 312 ticks, its position over 1"
        );
        assert_eq!(FaultKind::Watchdog.name(), "Watchdog");
    }

    /// A `fmt::Write` into a byte array (the crate is no_std without `alloc` in tests).
    struct Writer<'a>(&'a mut [u8], usize);

    impl core::fmt::Write for Writer<'_> {
        fn write_str(&mut self, s: &str) -> core::fmt::Result {
            let end = self.1 + s.len();
            self.0
                .get_mut(self.1..end)
                .ok_or(core::fmt::Error)?
                .copy_from_slice(s.as_bytes());
            self.1 = end;
            Ok(())
        }
    }

    #[test]
    fn fault_kinds_keep_their_indices_and_servo_stuck_is_appended() {
        let cases: [(FaultKind, &[u8]); 6] = [
            (FaultKind::EmergencyStop, &[0]),
            (FaultKind::ServoError { bits: 0x20 }, &[1, 0x20]),
            (FaultKind::ServoMissing { cycles: 3 }, &[2, 3]),
            (FaultKind::SetpointTimeout, &[3]),
            (FaultKind::Watchdog, &[4]),
            // 300 = 0b10_0101100 -> 0xAC 0x02; 2 -> 0x02.
            (
                FaultKind::ServoStuck {
                    goal_range: 300,
                    present_range: 2,
                },
                &[5, 0xAC, 0x02, 0x02],
            ),
        ];
        for (kind, bytes) in cases {
            let mut buf = [0u8; 8];
            let got = postcard::to_slice(&kind, &mut buf).unwrap();
            assert_eq!(&got[..], bytes, "{kind:?}");
            assert_eq!(postcard::from_bytes::<FaultKind>(bytes).unwrap(), kind);
        }
    }
}

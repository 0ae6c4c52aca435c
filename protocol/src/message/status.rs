//! State, counters and settings of the board.

use super::{Direction, Fault};
use crate::MAX_JOINTS;

/// State of the board's safety state machine.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum RunState {
    /// Torque off.
    Idle,
    /// Torque on, holding a posture.
    Standing,
    /// Moving from the present posture to the first slice of a gait.
    Ramping,
    /// Playing a gait.
    Walking,
    /// Finishing the current step before standing.
    Stopping,
    /// Following streamed setpoints.
    Streaming,
    /// Stopped by a fault (see [`Status::fault`]) until `ClearFault`.
    Fault,
    /// Starting up: pinging the servos of the stored joint map and reading the gait store; Idle
    /// follows within a few bus cycles. (Last, so the older states keep their wire indices.)
    Boot,
}

impl RunState {
    /// The state's one-word key, as Python's `status()["state"]` and the environment's `info`
    /// hold it ("Idle", "Streaming", ...): stable, for programs to compare against.
    pub const fn key(self) -> &'static str {
        match self {
            RunState::Idle => "Idle",
            RunState::Standing => "Standing",
            RunState::Ramping => "Ramping",
            RunState::Walking => "Walking",
            RunState::Stopping => "Stopping",
            RunState::Streaming => "Streaming",
            RunState::Fault => "Fault",
            RunState::Boot => "Boot",
        }
    }

    /// The state as a user reads it: the firmware's name, with what it means for the robot where
    /// that is not obvious. Every door (CLI, Python, errors) prints this.
    pub const fn name(self) -> &'static str {
        match self {
            RunState::Idle => "Idle (torque off)",
            RunState::Standing => "Standing",
            RunState::Ramping => "Ramping (to the first slice)",
            RunState::Walking => "Walking",
            RunState::Stopping => "Stopping (at the end of the step)",
            RunState::Streaming => "Streaming",
            RunState::Fault => "Fault (torque off)",
            RunState::Boot => "Boot (finding the servos, reading the gait store)",
        }
    }
}

impl core::fmt::Display for RunState {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// Where playback is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PlaybackPosition {
    pub slot: u8,
    pub direction: Direction,
    /// Step period scale, 1e-3.
    pub period_scale: u16,
    /// Steps completed.
    pub step: u32,
    pub slice: u16,
}

/// An upload in progress.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct UploadProgress {
    pub slot: u8,
    pub received: u32,
    pub total_len: u32,
}

/// Counters since boot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Counters {
    pub cycles: u32,
    pub missed_deadlines: u32,
    /// Servo replies that did not come in time.
    pub bus_timeouts: u32,
    /// Servo replies that came but could not be used: a failed CRC, or a packet that checks but
    /// is not the expected status (wrong instruction or data length).
    pub crc_errors: u32,
    /// Frames from the host that could not be decoded.
    pub rejected_frames: u32,
    /// Telemetry records dropped because the host did not read them in time.
    pub telemetry_dropped: u32,
    /// Goal moves the board cut short to what the servo can move in one bus cycle (a streamed
    /// setpoint further away, or the torque bias after a stiffness change while walking:
    /// `firmware::goal_step`), one per joint per cycle (added at the end of the counters: protocol
    /// version 9).
    pub rate_limited: u32,
}

/// Answer to [`crate::Request::GetStatus`].
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Status {
    pub state: RunState,
    /// The fault that stopped the robot, until cleared.
    pub fault: Option<Fault>,
    pub playback: Option<PlaybackPosition>,
    pub upload: Option<UploadProgress>,
    /// Bit j set when joint j's servo has torque on.
    pub torque_enabled: u32,
    pub counters: Counters,
    /// The worst servo at or past a heat or supply warning limit now (appended: protocol
    /// version 8), `None` when all are within.
    pub health_warning: Option<super::HealthAlarm>,
    /// The servo whose reading stopped the last walk at the end of its step, until the next
    /// `Play` (appended: protocol version 8).
    pub health_stop: Option<super::HealthAlarm>,
}

/// Run-time settings of one joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct JointSettings {
    /// Servo stiffness for the torque bias, mN m/rad.
    pub stiffness: u32,
    /// Limits, 1e-4 rad.
    pub min: i16,
    pub max: i16,
    pub torque_enabled: bool,
}

/// Answer to [`crate::Request::GetSettings`].
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Settings {
    /// Bus baud rate, bit/s.
    pub baud: u32,
    /// Bus cycle rate, Hz.
    pub cycle_hz: u16,
    /// Telemetry every this many cycles outside streaming (0 = off); streaming's proprioception
    /// follows `StreamConfig::feedback_every` instead.
    pub telemetry_every: u16,
    pub joints: heapless::Vec<JointSettings, MAX_JOINTS>,
    /// Heat and supply limits (appended: protocol version 8).
    pub health: super::HealthLimits,
}

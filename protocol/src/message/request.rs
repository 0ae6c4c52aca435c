//! Requests from the host and their parameters.

use crate::MAX_CHUNK_LEN;
use crate::gait::GaitHeader;

// Messages live in fixed-size buffers on a board without a heap: boxing the large variant is not
// an option, and the size is bounded by MAX_JOINTS / MAX_CHUNK_LEN.
#[allow(clippy::large_enum_variant)]
/// A request. Replies are named per variant; [`crate::Response::Error`] is possible for all.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Request {
    /// Reply: `DeviceInfo`.
    GetDeviceInfo,
    /// Reply: `Status`.
    GetStatus,
    /// Reply: `Slots`.
    ListGaits,
    /// Starts an upload into `slot` (replacing an unfinished one). `total_len` must equal
    /// `header.table_len()`. Reply: `Ack`.
    UploadBegin {
        slot: u8,
        header: GaitHeader,
        total_len: u32,
    },
    /// Table bytes at `offset`; chunks must arrive in order without gaps. Reply: `ChunkAccepted`.
    UploadChunk {
        offset: u32,
        data: heapless::Vec<u8, MAX_CHUNK_LEN>,
    },
    /// Ends the upload: `crc` is the CRC-32 of all `total_len` bytes. Reply: `Committed`.
    UploadCommit { crc: u32 },
    /// Drops the upload in progress; the slot keeps its old table. Reply: `Ack`.
    UploadAbort,
    /// Empties a slot (not the one playing). Reply: `Ack`.
    DeleteGait { slot: u8 },
    /// Starts playback from standing, ramping from the present posture to the first slice.
    /// Reply: `Ack`.
    Play(PlayCommand),
    /// Stops at the end of the current step (never mid-swing). Reply: `Ack`.
    Stop,
    /// Changes the step period scale while playing (1e-3, 1000 = as planned). Reply: `Ack`.
    SetPeriodScale { scale: u16 },
    /// Reply: `Settings`.
    GetSettings,
    /// Bus baud rate (bit/s) and bus cycle rate (Hz); only when not moving. Reply: `Ack`.
    SetBus { baud: u32, cycle_hz: u16 },
    /// Servo stiffness for the torque bias of `joint`, mN m/rad. Reply: `Ack`.
    SetStiffness { joint: u8, stiffness: u32 },
    /// Limits of `joint`, 1e-4 rad. Reply: `Ack`.
    SetLimits { joint: u8, min: i16, max: i16 },
    /// Torque on or off for one servo or all. Reply: `Ack`.
    SetTorque { servos: ServoSelect, enable: bool },
    /// Reboots servos (clears a hardware error; torque is off afterwards). Reply: `Ack`.
    RebootServos { servos: ServoSelect },
    /// Torque off on every servo at once, from any state. Reply: `Ack`.
    EmergencyStop,
    /// Leaves the fault state once its cause is gone. Reply: `Ack`.
    ClearFault,
    /// Sends `Telemetry` every `every` bus cycles (0 = off) outside streaming (idle, standing,
    /// playback, fault). Streaming sends `Proprioception` at its own rate,
    /// [`StreamConfig::feedback_every`], whatever this says. Reply: `Ack`.
    SetTelemetry { every: u16 },
    /// Enters streaming mode from standing. Reply: `Ack`.
    EnterStreaming(StreamConfig),
    /// Leaves streaming mode, holding the last setpoint. Reply: `Ack`.
    LeaveStreaming,
    /// The servo ID of each joint of the table in `slot`, or with `None` of the selected gait (the
    /// one playing, last played or last uploaded), so a host that did not upload the table can name
    /// the joints. Reply: `JointMap`.
    GetJointMap { slot: Option<u8> },
    /// Plays `slot` next, without standing still: at the next step boundary of an endless gait,
    /// or once a counted gait has played its steps. Checked when queued with
    /// [`crate::switch::check_switch`] against the gait it follows (refused with
    /// [`crate::ProtocolError::Switch`]). Reply: `Ack`.
    QueueGait(QueueCommand),
    /// Drops every queued gait; the one playing plays on. Reply: `Ack`.
    ClearQueue,
    /// Sets the gaits [`Request::Steer`] blends, checked with [`crate::steer::check_side`]
    /// (refused with [`crate::ProtocolError::Steer`]); not while a steered walk plays.
    /// Reply: `Ack`.
    SetSteerFamily(crate::SteerFamily),
    /// The descending command: from standing, walks the family blended for the heading until
    /// `Stop`; while steering, the new heading and speed take over at the next step boundary (the
    /// blend moving by at most one side gait per boundary). Reply: `Ack`.
    Steer(crate::SteerCommand),
    /// Sets up the perturbation platform for the next runs, checked with
    /// [`crate::PlatformSetup::check`] against the joint map (refused with
    /// [`crate::ProtocolError::Platform`]); only when not moving. The board then pings the servo
    /// and writes its profile velocity at its next bus cycle ([`Request::GetPlatform`] says how
    /// that went), and from then on writes the platform's goal in every goal Sync Write. `Play`
    /// refuses a step beyond the run's steps and a servo that did not answer. Reply: `Ack`.
    SetPlatform(crate::PlatformSetup),
    /// No platform any more (its servo keeps its last goal). Reply: `Ack`.
    ClearPlatform,
    /// Reply: `Platform`.
    GetPlatform,
    /// Heat and supply limits, checked with [`crate::HealthLimits::check`] (refused with
    /// `InvalidSetting { setting: HealthLimits, .. }`). Reply: `Ack`. (Appended: protocol
    /// version 8.)
    SetHealthLimits(crate::HealthLimits),
    /// Reads registers of (or pings) one servo on the board's bus between bus cycles (appended:
    /// protocol version 9); a read still pending is replaced. Collect with `GetServoRead`.
    ReadServo(crate::ServoRead),
    /// The last finished servo read (appended: protocol version 9).
    GetServoRead,
}

/// Which servos a command addresses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ServoSelect {
    All,
    /// The servo of one joint (index into the joint map).
    Joint(u8),
}

/// Playback direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Direction {
    Forward,
    /// Slices in reverse order (walking backward on the same footpaths).
    Backward,
}

/// How many steps to play.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Steps {
    /// Until `Stop`.
    Continuous,
    /// This many whole steps, then stop at the end of the last.
    Count(u32),
}

/// Parameters of [`Request::Play`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PlayCommand {
    pub slot: u8,
    pub direction: Direction,
    /// Step period scale, 1e-3 (2000 = half speed).
    pub period_scale: u16,
    pub steps: Steps,
}

impl PlayCommand {
    /// The gait in `slot` at `period_scale` (1e-3) in `direction`, for `steps`.
    pub const fn new(slot: u8, direction: Direction, period_scale: u16, steps: Steps) -> Self {
        Self {
            slot,
            direction,
            period_scale,
            steps,
        }
    }

    /// The gait in `slot` forward at its planned period, for `steps`.
    pub const fn forward(slot: u8, steps: Steps) -> Self {
        Self::new(
            slot,
            Direction::Forward,
            crate::units::PERIOD_SCALE_ONE,
            steps,
        )
    }
}

impl Direction {
    /// `Backward` when `backward`, else `Forward`.
    pub const fn backward_if(backward: bool) -> Self {
        if backward {
            Self::Backward
        } else {
            Self::Forward
        }
    }

    /// `forward` or `backward`: the word every door prints (status lines, trial READMEs).
    pub const fn name(self) -> &'static str {
        match self {
            Self::Forward => "forward",
            Self::Backward => "backward",
        }
    }
}

/// Parameters of [`Request::QueueGait`]: a [`PlayCommand`] that waits for its step boundary. On
/// the wire it is exactly a `PlayCommand` (postcard writes a newtype as what it wraps).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct QueueCommand(pub PlayCommand);

/// Parameters of [`Request::EnterStreaming`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StreamConfig {
    /// Bus cycles without a new setpoint after which the board holds position and faults with
    /// `FaultKind::SetpointTimeout` (at least 1).
    pub timeout_cycles: u16,
    /// Sends `Proprioception` every this many bus cycles (1 = every cycle; 0 is taken as 1),
    /// independent of [`Request::SetTelemetry`], which governs the other states' `Telemetry`.
    pub feedback_every: u16,
}

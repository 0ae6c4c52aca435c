//! Per-cycle traffic: streaming setpoints and proprioception (closed loop), and playback telemetry.

use crate::MAX_JOINTS;

/// One joint's target in a [`Setpoint`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct JointSetpoint {
    /// Joint angle, 1e-4 rad (clamped to the joint limits by the board).
    pub angle: i16,
    /// Torque feed-forward, mN m: the board adds `torque / stiffness` to the angle (the torque
    /// bias); `None` means none.
    pub torque: Option<i16>,
}

/// Targets of every joint for the next bus cycle (streaming mode).
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Setpoint {
    /// Host's counter, echoed as [`Proprioception::setpoint_seq`].
    pub seq: u32,
    /// One entry per joint of the joint map, in its order.
    pub joints: heapless::Vec<JointSetpoint, MAX_JOINTS>,
}

/// Bits of [`JointFeedback::flags`].
pub mod feedback_flags {
    /// The servo did not answer this cycle; the other fields repeat the last good values.
    pub const NO_REPLY: u8 = 1 << 0;
    /// The servo's reply failed its CRC.
    pub const CRC_ERROR: u8 = 1 << 1;
    /// The commanded position was clamped to a joint limit.
    pub const CLAMPED: u8 = 1 << 2;
    /// Torque is off.
    pub const TORQUE_OFF: u8 = 1 << 3;
    /// The servo's status carried the Alert bit: a hardware error is latched (`GetStatus` names it).
    pub const ALERT: u8 = 1 << 4;
    /// The servo's last heat or supply reading is at or past a warning limit
    /// ([`crate::HealthLimits`]; appended: protocol version 8).
    pub const HEALTH_WARN: u8 = 1 << 5;
    /// ... at or past a stop limit: a walk stops at the end of its step.
    pub const HEALTH_STOP: u8 = 1 << 6;
}

/// One joint's state in one bus cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct JointFeedback {
    /// Goal this cycle's Sync Write carried (after bias and clamping; the held goal when the cycle
    /// wrote none), joint angle in 1e-4 rad.
    pub commanded: i16,
    /// Present position, joint angle in 1e-4 rad (wrapped to +-pi around the zero offset).
    pub present: i16,
    /// Present velocity, 1e-3 rad/s in the joint frame.
    pub velocity: i16,
    /// Raw register 126: MX-28 present load in 0.1 % of max, MX-64 present current in about 3.36 mA.
    pub load: i16,
    /// The servo's Hardware Error Status (bit 5 overload, 4 electrical shock, 3 encoder,
    /// 2 overheat, 0 input voltage).
    pub error: u8,
    /// [`feedback_flags`].
    pub flags: u8,
}

/// Bus counters carried in every telemetry record (totals since boot).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BusStats {
    /// Duration of this cycle's bus transaction, us.
    pub cycle_us: u32,
    pub timeouts: u32,
    /// Replies that failed their CRC or were malformed (as `Counters::crc_errors`).
    pub crc_errors: u32,
    pub missed_deadlines: u32,
}

/// Telemetry of one bus cycle during playback.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Telemetry {
    /// Board time at the start of the cycle, us since boot.
    pub time_us: u64,
    pub cycle: u32,
    /// Steps completed since `Play`.
    pub step: u32,
    /// Slice of the table the targets were interpolated from.
    pub slice: u16,
    pub joints: heapless::Vec<JointFeedback, MAX_JOINTS>,
    pub bus: BusStats,
    /// The perturbation platform's servo, while one is set up (appended: protocol version 7).
    pub platform: Option<super::PlatformFeedback>,
    /// The board's run state in this cycle (appended: protocol version 8): `Fault` from the first
    /// cycle after a fault stopped the robot, so a recording shows where the walk ended and why
    /// (`GetStatus` names the fault).
    pub state: super::RunState,
    /// Each joint's servo's last heat and supply reading (appended: protocol version 8), in joint
    /// order; read one servo per bus cycle, so a value can be up to one round of the chain old.
    pub health: heapless::Vec<super::ServoHealth, MAX_JOINTS>,
}

/// Feedback of one bus cycle in streaming mode, every [`crate::StreamConfig::feedback_every`]
/// cycles (whatever [`crate::Request::SetTelemetry`] says: that governs playback telemetry only).
///
/// A record holds together: the setpoint it names, its age and every joint's `commanded` are what
/// this cycle's Sync Write carried, taken when the cycle was planned (a setpoint that arrives while
/// the cycle is on the bus waits for the next one); `present`, `velocity` and `load` are this
/// cycle's Sync Read (the last good values, flagged `NO_REPLY`, for a servo that did not answer).
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Proprioception {
    /// Board time at the start of the cycle, us since boot.
    pub time_us: u64,
    pub cycle: u32,
    /// `seq` of the setpoint this cycle's Sync Write carried; 0 before the first setpoint since
    /// `EnterStreaming` (the standing posture is held), so number setpoints from 1.
    pub setpoint_seq: u32,
    /// Cycles this setpoint has been written, this one included: 1 = it arrived since the previous
    /// cycle started (fresh); more = held. Past `StreamConfig::timeout_cycles` the board goes safe.
    pub setpoint_age: u16,
    pub joints: heapless::Vec<JointFeedback, MAX_JOINTS>,
    pub bus: BusStats,
}

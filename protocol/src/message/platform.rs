//! The perturbation platform's messages: how the host sets it up for the next run, what the board
//! knows of it, and its servo's line in each telemetry record (the rule behind them:
//! [`crate::platform`]).

/// Where the platform goes at the perturbed step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PlatformMove {
    /// To [`PlatformSetup::rise`] (the lab's usual perturbation).
    Rise,
    /// To [`PlatformSetup::fall`].
    Fall,
}

/// Parameters of [`crate::Request::SetPlatform`]: the auxiliary servo that moves a platform under
/// one foot, and when it moves. Checked with [`PlatformSetup::check`] on both sides.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PlatformSetup {
    /// The platform servo's bus ID (the lab's: 22, after the joints' 0-21); not a joint's ID.
    pub servo_id: u8,
    /// Goal positions, servo ticks (0 ..= 4095).
    pub rest: u16,
    pub rise: u16,
    pub fall: u16,
    /// Profile Velocity register value (0.229 rev/min; 0 = as fast as the servo goes), written
    /// when the board sets the servo up.
    pub profile_velocity: u16,
    pub moves: PlatformMove,
    /// The perturbed step, counted from 0 (the steps walked since `Play` before it): at its first
    /// bus cycle the goal goes to `rise` or `fall`.
    pub step: u32,
    /// Bus cycles at the moved goal before it goes back to `rest` (at least 1; the lab's: 2).
    pub hold_cycles: u16,
}

/// What the board knows of the platform servo (reply to [`crate::Request::GetPlatform`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PlatformState {
    /// Set up; the board pings the servo and writes its profile velocity at its next bus cycle.
    Checking,
    /// The servo answered at set-up and took its profile velocity; `present` is its position
    /// then, ticks.
    Ready { present: u16 },
    /// The servo did not answer at set-up (ping, a write or the position read failed): `Play`
    /// is refused until it is set up again.
    NotAnswering,
}

/// Reply to [`crate::Request::GetPlatform`]: the platform set up, and its servo's state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PlatformStatus {
    pub setup: PlatformSetup,
    pub state: PlatformState,
}

/// The platform servo in one bus cycle (in [`crate::Telemetry::platform`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PlatformFeedback {
    pub servo_id: u8,
    /// Goal this cycle's Sync Write carried, ticks (the held goal when the cycle wrote none).
    pub goal: u16,
    /// Present position, ticks (the last good one when the servo did not answer, flagged).
    pub present: u16,
    /// [`crate::feedback_flags`] (`NO_REPLY`, `CRC_ERROR`).
    pub flags: u8,
}

//! Safety state machine of the controller: which state the robot is in and which events move it.
//! Pure data, no I/O: the controller feeds events and acts on the state (drive goals, torque off).
//! The states are those of the protocol's `RunState`, with the fault split into
//! `Safe(reason)` and `EStop`.
//!
//! ```text
//!  Boot ─BootDone─> Idle ─TorqueOn─> Standing ─Start─> Ramping ─RampDone─> Walking ─Stop─> Stopping
//!                    ^ └──TorqueOff──┘ ^ │ ^  ^          │Stop               │StepsDone    │EndOfStep,
//!                    │                 │ │ │  └──────────┘                   v             │StepsDone
//!                    │                 │ │ └─────────────────────────────  Standing <────┘
//!                    │                 │ └EnterStreaming─> Streaming ─LeaveStreaming─┘
//!  Safe(r) / EStop ─ClearFault─┘   any ─Fault(r)─> Safe(r)   any ─EStop─> EStop
//!  Idle / Standing / Safe / EStop ─Reboot─> Boot
//!  Ramping / Walking ─Queue─> itself        Walking ─Switch─> Walking (the queued gait, at a boundary)
//!  Idle / Standing / Ramping / Walking / Stopping ─ClearQueue─> itself
//!  Ramping / Walking ─Steer─> itself (a new heading for the next step boundary)
//! ```
//!
//! Gait switching adds no state: a queued gait waits in the controller while the robot ramps or
//! walks, and `Switch` is the step boundary at which it takes over. Stopping refuses `Queue` and
//! `Switch` (a stop has been promised at the end of this step), and every state but Ramping and
//! Walking drops the queue on entry, so a lost host or a fault never leaves a gait waiting.

pub mod health;
#[cfg(test)]
mod health_tests;
pub mod stuck;

pub use stuck::{StuckDetector, StuckLimits};

/// Why the robot went into the safe state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum SafeReason {
    /// The servo of `joint` (bus `id`) reported a hardware error (`error` = its Hardware Error
    /// Status bits, or the status packet's error number).
    ServoError { joint: u8, id: u8, error: u8 },
    /// The servo of `joint` (bus `id`) did not answer usably for `cycles` consecutive bus cycles.
    ServoMissing { joint: u8, id: u8, cycles: u8 },
    /// The servo of `joint` (bus `id`) did not follow its goal: over one window its goal moved over
    /// `goal_range` ticks, its present position over only `present_range` ([`stuck`]).
    ServoStuck {
        joint: u8,
        id: u8,
        goal_range: u16,
        present_range: u16,
    },
    /// Streaming mode got no new setpoint in time.
    SetpointTimeout,
    /// The watchdog reset a hung firmware.
    Watchdog,
}

/// State of the controller. The host sees it as [`protocol::RunState`] (`link::convert`), whose
/// variants say what each state means; here a fault keeps its reason, and the host's emergency
/// stop is a state of its own.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum State {
    /// [`protocol::RunState::Boot`]: servos are being found and configured.
    Boot,
    /// [`protocol::RunState::Idle`]; feedback is still read.
    Idle,
    /// [`protocol::RunState::Standing`].
    Standing,
    /// [`protocol::RunState::Ramping`].
    Ramping,
    /// [`protocol::RunState::Walking`].
    Walking,
    /// [`protocol::RunState::Stopping`].
    Stopping,
    /// [`protocol::RunState::Streaming`].
    Streaming,
    /// [`protocol::RunState::Fault`]: goals are no longer written, telemetry goes on.
    Safe(SafeReason),
    /// Torque off on every servo, by the host's order ([`protocol::RunState::Fault`] on the wire).
    EStop,
}

/// What can happen to the controller.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Event {
    /// Every servo of the joint map answered.
    BootDone,
    /// Host: torque on (hold the present posture).
    TorqueOn,
    /// Host: torque off.
    TorqueOff,
    /// Host: start playing the selected gait.
    Start,
    /// The ramp reached the first slice.
    RampDone,
    /// Host: stop (at the end of the step).
    Stop,
    /// Playback crossed the end of a step.
    EndOfStep,
    /// Playback finished the requested number of steps (at the end of a step).
    StepsDone,
    /// Host: follow streamed setpoints.
    EnterStreaming,
    /// Host: stop streaming, hold the last setpoint.
    LeaveStreaming,
    /// Host: emergency stop.
    EStop,
    /// A servo fault, a setpoint timeout or the watchdog.
    Fault(SafeReason),
    /// Host: the cause of the fault is gone; go to Idle (torque off).
    ClearFault,
    /// Host: reboot the servos and look for them again.
    Reboot,
    /// Host: play another gait next, at a step boundary (checked by `protocol::switch` first).
    Queue,
    /// Host: drop the queued gaits.
    ClearQueue,
    /// Playback reached the step boundary at which a queued gait takes over.
    Switch,
    /// Host: a new heading and speed for the steered walk, from its next step boundary (a steered
    /// walk starts with `Start`).
    Steer,
}

/// An event the current state does not accept; the state stays as it was.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Refused {
    pub state: State,
    pub event: Event,
}

impl State {
    /// The state after `event`, or `Refused` (the state is unchanged then).
    pub fn next(self, event: Event) -> Result<State, Refused> {
        use Event as E;
        use State as S;
        let next = match (self, event) {
            // An emergency stop is accepted everywhere and wins over everything but itself.
            (_, E::EStop) => S::EStop,
            // The first fault is the one reported; later ones do not overwrite it.
            (S::Safe(r), E::Fault(_)) => S::Safe(r),
            (S::EStop, E::Fault(_)) => S::EStop,
            (_, E::Fault(r)) => S::Safe(r),
            (S::Boot, E::BootDone) => S::Idle,
            (S::Idle | S::Standing, E::TorqueOn) => S::Standing,
            (S::Idle | S::Standing, E::TorqueOff) => S::Idle,
            (S::Idle | S::Standing, E::Start) => S::Ramping,
            (S::Idle | S::Standing, E::Stop) => self,
            (S::Idle | S::Standing, E::EnterStreaming) => S::Streaming,
            (S::Idle | S::Standing | S::Safe(_) | S::EStop, E::Reboot) => S::Boot,
            (S::Safe(_) | S::EStop, E::ClearFault) => S::Idle,
            (S::Ramping, E::RampDone) => S::Walking,
            // Stopping a ramp holds where it got to: the gait never started, there is no step to end.
            (S::Ramping, E::Stop) => S::Standing,
            (S::Walking, E::Stop) => S::Stopping,
            (S::Walking, E::EndOfStep) => S::Walking,
            (S::Walking | S::Stopping, E::StepsDone) => S::Standing,
            (S::Stopping, E::EndOfStep) => S::Standing,
            (S::Stopping, E::Stop) => S::Stopping,
            (S::Streaming, E::LeaveStreaming | E::Stop) => S::Standing,
            (S::Ramping | S::Walking, E::Queue) => self,
            (S::Idle | S::Standing | S::Ramping | S::Walking | S::Stopping, E::ClearQueue) => self,
            (S::Walking, E::Switch) => S::Walking,
            (S::Ramping | S::Walking, E::Steer) => self,
            (state, event) => return Err(Refused { state, event }),
        };
        Ok(next)
    }

    /// Whether the bus loop writes goal positions (and servos have torque on) in this state.
    pub fn drives_goals(self) -> bool {
        matches!(
            self,
            State::Standing | State::Ramping | State::Walking | State::Stopping | State::Streaming
        )
    }

    /// Whether the gait clock advances.
    pub fn plays(self) -> bool {
        matches!(self, State::Walking | State::Stopping)
    }

    /// Whether the flash may be written: never while anything moves, because a sector erase stalls
    /// XIP (and with it the bus loop) for tens of milliseconds.
    pub fn allows_flash_writes(self) -> bool {
        matches!(
            self,
            State::Boot | State::Idle | State::Standing | State::Safe(_) | State::EStop
        )
    }
}

/// Counts consecutive missed replies per servo and names the first servo that reaches the limit.
#[derive(Debug, Clone)]
pub struct MissCounter<const N: usize> {
    misses: [u8; N],
    limit: u8,
}

impl<const N: usize> MissCounter<N> {
    /// A servo is declared missing after `limit` consecutive misses (at least 1).
    pub fn new(limit: u8) -> Self {
        Self {
            misses: [0; N],
            limit: limit.max(1),
        }
    }

    /// Records one cycle for the servo of `joint` (bus `id`): `answered` resets its count.
    pub fn record(&mut self, joint: usize, id: u8, answered: bool) -> Option<SafeReason> {
        let m = self.misses.get_mut(joint)?;
        *m = if answered { 0 } else { m.saturating_add(1) };
        (*m >= self.limit).then_some(SafeReason::ServoMissing {
            joint: joint as u8,
            id,
            cycles: *m,
        })
    }

    /// Forgets all misses (after a reboot).
    pub fn reset(&mut self) {
        self.misses = [0; N];
    }
}

#[cfg(test)]
mod tests;

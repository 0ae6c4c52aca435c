//! Safety state machine of the controller: which state the robot is in and which events move it.
//! Pure data, no I/O: the controller feeds events and acts on the state (drive goals, torque off).
//!
//! ```text
//!  Boot ──BootDone──> Idle ──Start──> Ramping ──RampDone──> Walking ──Stop──> Stopping
//!                      ^  ^             │Stop                  │StepsDone      │EndOfStep / StepsDone
//!                      │  └─────────────┘                      v               v
//!                      └────────────────────────────────────  Idle <──────────┘
//!  any ──Fault(r)──> Safe(r)      any ──EStop──> EStop      Safe / EStop / Idle ──Reboot──> Boot
//! ```

/// Why the robot went into the safe state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum SafeReason {
    /// The servo reported a hardware error (`error` = its Hardware Error Status bits, or the status
    /// packet's error byte when the alert bit is set).
    ServoError { id: u8, error: u8 },
    /// The servo did not answer (or answered corrupt) for `cycles` consecutive bus cycles.
    ServoMissing { id: u8, cycles: u8 },
    /// The watchdog reset a hung firmware.
    Watchdog,
}

/// State of the controller.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum State {
    /// Servos are being found and configured; nothing moves.
    Boot,
    /// Servos hold their last goals; uploads and settings are allowed.
    Idle,
    /// Moving from the present positions to the first slice of the gait.
    Ramping,
    /// Playing the gait.
    Walking,
    /// Playing on until the end of the current step, then Idle.
    Stopping,
    /// A fault stopped playback; goals are no longer written, telemetry goes on.
    Safe(SafeReason),
    /// Torque off on every servo, by the host's order.
    EStop,
}

/// What can happen to the controller.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Event {
    /// Every servo of the joint map answered and was configured.
    BootDone,
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
    /// Host: emergency stop.
    EStop,
    /// A servo fault or the watchdog.
    Fault(SafeReason),
    /// Host: reboot the servos and configure them again.
    Reboot,
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
            (S::Idle, E::Start) => S::Ramping,
            (S::Idle, E::Stop) => S::Idle,
            (S::Idle | S::Safe(_) | S::EStop, E::Reboot) => S::Boot,
            (S::Ramping, E::RampDone) => S::Walking,
            // Stopping a ramp holds where it got to: the gait never started, there is no step to end.
            (S::Ramping, E::Stop) => S::Idle,
            (S::Walking, E::Stop) => S::Stopping,
            (S::Walking, E::EndOfStep) => S::Walking,
            (S::Walking | S::Stopping, E::StepsDone) => S::Idle,
            (S::Stopping, E::EndOfStep) => S::Idle,
            (S::Stopping, E::Stop) => S::Stopping,
            (state, event) => return Err(Refused { state, event }),
        };
        Ok(next)
    }

    /// Whether the bus loop writes goal positions in this state.
    pub fn drives_goals(self) -> bool {
        matches!(self, State::Ramping | State::Walking | State::Stopping | State::Idle)
    }

    /// Whether the gait clock advances.
    pub fn plays(self) -> bool {
        matches!(self, State::Walking | State::Stopping)
    }

    /// Whether the flash may be written: never while anything moves, because a sector erase stalls
    /// XIP (and with it the bus loop) for tens of milliseconds.
    pub fn allows_flash_writes(self) -> bool {
        matches!(self, State::Idle | State::Safe(_) | State::EStop | State::Boot)
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

    /// Records one cycle for the servo at `index` (with bus `id`): `answered` resets its count.
    pub fn record(&mut self, index: usize, id: u8, answered: bool) -> Option<SafeReason> {
        let m = self.misses.get_mut(index)?;
        *m = if answered { 0 } else { m.saturating_add(1) };
        (*m >= self.limit).then_some(SafeReason::ServoMissing { id, cycles: *m })
    }

    /// Forgets all misses (after a reboot).
    pub fn reset(&mut self) {
        self.misses = [0; N];
    }
}

#[cfg(test)]
mod tests;

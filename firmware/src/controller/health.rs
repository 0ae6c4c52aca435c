//! The controller's side of the heat and supply watch ([`crate::safety::health`]): which servo
//! the bus loop reads in this cycle's slack, what a reading does (a warning in the status, a
//! walk stopped at the end of its step naming the servo), the limits as a setting.

use dynamixel::master::ReplyFault;
use embedded_storage::nor_flash::NorFlash;
use protocol::{HealthAlarm, HealthLevel, HealthLimitError, HealthLimits, ServoHealth};

use super::{BusAction, Controller};
use crate::safety::{Event, State};
use crate::store::FlashWindow;

impl<F: NorFlash + FlashWindow> Controller<F> {
    /// The joint and bus ID whose heat and supply the bus loop reads after `action`, if it has
    /// the time: one servo per bus cycle in turn, in the actions that read feedback.
    pub(super) fn health_read_for(&mut self, action: BusAction) -> Option<(u8, u8)> {
        if !matches!(
            action,
            BusAction::Cycle | BusAction::ReadOnly | BusAction::WriteGains
        ) {
            return None;
        }
        let j = self.health.next_joint(self.joints.len())?;
        Some((j as u8, self.joints[j].id))
    }

    /// A heat and supply reading of `joint`'s servo `id` (Present Input Voltage, 0.1 V, and
    /// Present Temperature, degC). At a stop limit a walk stops at the end of its step (as
    /// `Stop` does) and the status names the servo until the next `Play`.
    pub fn health_reading(&mut self, joint: u8, id: u8, reading: ServoHealth) {
        let j = usize::from(joint);
        if self.joints.get(j).map(|c| c.id) != Some(id) {
            // The joint map changed while the read was on the bus.
            return;
        }
        let Some(alarm) = self.health.record(j, id, reading) else {
            return;
        };
        if alarm.level == HealthLevel::Stop
            && matches!(self.state, State::Ramping | State::Walking)
            && self.event(Event::Stop)
        {
            self.health_stop = Some(alarm);
        }
    }

    /// A heat and supply read whose reply was lost: counted with the cycle's lost replies
    /// (every lost reply is counted, whichever read it answered); it is not a miss, since the
    /// servo's feedback in the cycle's Sync Read decides whether it is there.
    pub fn health_reply_lost(&mut self, fault: ReplyFault) {
        match fault {
            ReplyFault::Timeout => self.counters.timeouts = self.counters.timeouts.wrapping_add(1),
            ReplyFault::Crc | ReplyFault::Malformed => {
                self.counters.crc_errors = self.counters.crc_errors.wrapping_add(1)
            }
            // A servo that answers with an error number is there; the cycle's feedback carries
            // it (ReplyFault is non-exhaustive: a new kind is not counted until it is named).
            _ => {}
        }
    }

    /// Each joint's servo's last heat and supply reading (zeros: not read yet).
    pub fn health_readings(&self) -> &[ServoHealth] {
        &self.health.readings()[..self.joints.len()]
    }

    /// The worst servo at or past a warning limit now.
    pub fn health_warning(&self) -> Option<HealthAlarm> {
        self.health.worst(self.joints.iter().map(|j| j.id))
    }

    /// The servo whose reading stopped the last walk, until the next `Play`.
    pub fn health_stop(&self) -> Option<HealthAlarm> {
        self.health_stop
    }

    /// `joint`'s telemetry flags from its last reading.
    pub(super) fn health_flags(&self, joint: usize) -> u8 {
        self.health.flags(joint)
    }

    pub fn health_limits(&self) -> HealthLimits {
        self.health.limits()
    }

    /// New heat and supply limits, in any state (a tighter limit acts at the next reading).
    pub fn set_health_limits(&mut self, limits: HealthLimits) -> Result<(), HealthLimitError> {
        limits.check()?;
        self.health.set_limits(limits);
        Ok(())
    }
}

//! The servos' heat and supply watch: each servo's last Present Temperature and Present Input
//! Voltage, read one servo per bus cycle in the cycle's slack (`bus_loop`), judged against
//! [`HealthLimits`]. A reading at a warning limit makes the worst servo the status's
//! `health_warning`; one at a stop limit makes the controller stop a walk at the end of its step,
//! naming the servo ([`HealthAlarm`]), before the servo's own shutdown would drop the robot.

use protocol::{HealthAlarm, HealthLevel, HealthLimits, ServoHealth, feedback_flags};

/// The watch over up to `N` joints.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HealthWatch<const N: usize> {
    limits: HealthLimits,
    readings: [ServoHealth; N],
    /// The joint read next.
    next: usize,
}

impl<const N: usize> HealthWatch<N> {
    pub fn new(limits: HealthLimits) -> Self {
        Self {
            limits,
            readings: [ServoHealth::default(); N],
            next: 0,
        }
    }

    pub fn limits(&self) -> HealthLimits {
        self.limits
    }

    /// New limits (checked by the caller with [`HealthLimits::check`]).
    pub fn set_limits(&mut self, limits: HealthLimits) {
        self.limits = limits;
    }

    /// Forgets the readings (the joint map changed: joint j is another servo).
    pub fn reset(&mut self) {
        self.readings = [ServoHealth::default(); N];
        self.next = 0;
    }

    /// The joint to read this cycle among `joints`, in turn (none without joints).
    pub fn next_joint(&mut self, joints: usize) -> Option<usize> {
        let n = joints.min(N);
        if n == 0 {
            return None;
        }
        let j = self.next % n;
        self.next = (j + 1) % n;
        Some(j)
    }

    /// Each joint's last reading.
    pub fn readings(&self) -> &[ServoHealth; N] {
        &self.readings
    }

    /// Takes `joint`'s reading; returns the alarm it raises at its own level, if any.
    pub fn record(&mut self, joint: usize, id: u8, reading: ServoHealth) -> Option<HealthAlarm> {
        let r = self.readings.get_mut(joint)?;
        *r = reading;
        self.alarm(joint, id)
    }

    /// `joint`'s alarm from its last reading (servo `id`).
    pub fn alarm(&self, joint: usize, id: u8) -> Option<HealthAlarm> {
        let reading = *self.readings.get(joint)?;
        let (kind, level, value) = self.limits.classify(reading)?;
        Some(HealthAlarm {
            joint: joint as u8,
            id,
            kind,
            level,
            value,
            limit: self.limits.limit(kind, level),
        })
    }

    /// The worst alarm among the joints whose servos are `ids` (a stop before a warning, the lowest
    /// joint first among equals).
    pub fn worst(&self, ids: impl Iterator<Item = u8>) -> Option<HealthAlarm> {
        let mut worst: Option<HealthAlarm> = None;
        for (j, id) in ids.enumerate().take(N) {
            if let Some(a) = self.alarm(j, id) {
                let better = match worst {
                    None => true,
                    Some(w) => w.level == HealthLevel::Warn && a.level == HealthLevel::Stop,
                };
                if better {
                    worst = Some(a);
                }
            }
        }
        worst
    }

    /// `joint`'s telemetry flags: [`feedback_flags::HEALTH_WARN`] or `HEALTH_STOP`.
    pub fn flags(&self, joint: usize) -> u8 {
        match self.alarm(joint, 0).map(|a| a.level) {
            Some(HealthLevel::Warn) => feedback_flags::HEALTH_WARN,
            Some(HealthLevel::Stop) => feedback_flags::HEALTH_STOP,
            None => 0,
        }
    }
}

//! What the controller makes of a finished bus action: feedback per joint, missed replies, servo
//! errors (with a read of the Hardware Error Status to name them), torque bookkeeping, telemetry.

use dynamixel::master::{CycleStats, Reply, ReplyFault};
use embedded_storage::nor_flash::NorFlash;

use super::{BusAction, Controller, CyclePlan, Outcome};
use crate::playback::MAX_JOINTS;
use crate::safety::{Event, SafeReason, State};
use crate::store::FlashWindow;
use crate::telemetry::{JointSample, Record, flags};

impl<F: NorFlash + FlashWindow> Controller<F> {
    /// Takes in what the bus action of `plan` gave: replies (one per joint, for Cycle and ReadOnly),
    /// statistics, and `late_us` = how late the cycle started. Updates feedback, counts misses and
    /// errors, moves the state machine, and queues telemetry.
    pub fn complete(
        &mut self,
        plan: &CyclePlan,
        outcome: Outcome,
        replies: &[Reply],
        late_us: u32,
    ) {
        if !matches!(
            plan.action,
            BusAction::Cycle | BusAction::ReadOnly | BusAction::WriteGains
        ) {
            // Torque switched, servos rebooted, an error read: no window spans that.
            self.stuck.reset();
        }
        self.counters.cycles = self.counters.cycles.wrapping_add(1);
        self.counters.jitter_us = late_us;
        self.counters.max_jitter_us = self.counters.max_jitter_us.max(late_us);
        match (plan.action, outcome) {
            (BusAction::TorqueOn, Outcome::Done(Ok(()))) => {
                self.torque_sent = true;
                self.torque_unknown = false;
                self.gains_written = plan.gain_gen;
            }
            (BusAction::TorqueOff, Outcome::Done(Ok(()))) => {
                self.torque_sent = false;
                self.torque_unknown = false;
            }
            (BusAction::Reboot { joints }, Outcome::Done(r)) => {
                // Rebooted servos come back with torque off; Boot then looks for all of them. If
                // only some were rebooted the others may still hold torque: Idle turns it off.
                self.reboot_pending = None;
                let n = self.joints.len();
                if n == 0 || joints.count_ones() as usize >= n {
                    self.torque_sent = false;
                }
                if r.is_err() {
                    self.counters.bus_errors = self.counters.bus_errors.wrapping_add(1);
                }
            }
            (BusAction::ReadHardwareError { joint }, Outcome::HardwareError(r)) => {
                self.hw_error_pending = None;
                if let (Ok(bits), State::Safe(SafeReason::ServoError { joint: j, id, .. })) =
                    (r, self.state)
                    && j == joint
                {
                    let before = self.state;
                    self.state = State::Safe(SafeReason::ServoError {
                        joint,
                        id,
                        error: bits,
                    });
                    crate::device_log::transition(
                        before,
                        self.state,
                        crate::device_log::Cause::ErrorBits,
                    );
                }
            }
            (BusAction::PlatformCheck { id, .. }, Outcome::PlatformChecked(r)) => {
                self.platform_checked(id, r);
            }
            // No servos: the record still tells the host the board is alive and in which state.
            (BusAction::Nothing, _) => self.queue_telemetry(plan, &CycleStats::default()),
            (BusAction::WriteGains, Outcome::Feedback(Ok(stats))) => {
                self.gains_written = plan.gain_gen;
                self.take_replies(plan, replies);
                self.take_platform_reply(plan, replies);
                self.queue_telemetry(plan, &stats);
            }
            (BusAction::Cycle | BusAction::ReadOnly, Outcome::Feedback(Ok(stats))) => {
                self.take_replies(plan, replies);
                self.take_platform_reply(plan, replies);
                self.queue_telemetry(plan, &stats);
            }
            (_, Outcome::Done(Err(_)) | Outcome::Feedback(Err(_))) => {
                self.counters.bus_errors = self.counters.bus_errors.wrapping_add(1);
            }
            _ => {}
        }
    }

    /// The platform servo's reply, after the joints' in a goal cycle's Sync Read.
    fn take_platform_reply(&mut self, plan: &CyclePlan, replies: &[Reply]) {
        if plan.platform.is_some()
            && plan.reply_count() > plan.n
            && let Some(reply) = replies.get(plan.n)
        {
            self.platform_reply(reply);
        }
    }

    fn take_replies(&mut self, plan: &CyclePlan, replies: &[Reply]) {
        // A reboot still pending means these replies were read before it (the host's command came
        // while the bus task awaited them): they describe the servos as the reboot is about to
        // change them, so a latched error in them must not fault the Boot waiting for the reboot,
        // and they do not count as found.
        let stale = self.reboot_pending.is_some();
        // A flash operation (upload, delete; never while moving) ran while this cycle's replies
        // were due: a missing reply is the stalled chip's doing, so it neither counts towards the
        // miss limit nor clears a run of misses. Replies that did come are used as usual.
        let flash_stalled = self.flash_ops != self.flash_ops_at_plan;
        let n = self.joints.len().min(plan.n).min(replies.len());
        // A stuck-rule sample is a cycle that wrote goals the servos are meant to follow.
        let sample =
            matches!(plan.action, BusAction::Cycle | BusAction::WriteGains) && self.torque_sent;
        if !sample {
            self.stuck.reset();
        }
        for (j, reply) in replies.iter().enumerate().take(n) {
            let id = self.joints[j].id;
            self.reply_flags[j] = match reply {
                Ok(_) | Err(ReplyFault::Status(_)) => 0,
                Err(ReplyFault::Crc | ReplyFault::Malformed) => flags::NO_REPLY | flags::CRC_ERROR,
                Err(_) => flags::NO_REPLY,
            };
            let usable = match reply {
                Ok(fb) => {
                    self.present[j] = *fb;
                    if !stale {
                        self.known[j] = true;
                    }
                    if fb.alert && !stale {
                        self.fault_servo(j, id, 0);
                    }
                    true
                }
                Err(ReplyFault::Status(e)) => {
                    // A servo that answers with an error number is there, but its data is not.
                    if !stale {
                        self.fault_servo(j, id, e.0);
                    }
                    true
                }
                Err(ReplyFault::Timeout) => {
                    self.counters.timeouts = self.counters.timeouts.wrapping_add(1);
                    false
                }
                // A malformed reply (checks, but is not the status asked for) is as unusable as
                // one that fails its CRC, and is counted with them: every lost reply is counted.
                Err(ReplyFault::Crc | ReplyFault::Malformed) => {
                    self.counters.crc_errors = self.counters.crc_errors.wrapping_add(1);
                    false
                }
                Err(_) => false,
            };
            if stale || (flash_stalled && !usable) {
                continue;
            }
            if let Some(reason) = self.misses.record(j, id, usable) {
                self.event(Event::Fault(reason));
            }
            if let (true, Ok(fb)) = (sample, reply) {
                let goal = plan.goals[j].position;
                if let Some(reason) = self.stuck.record(j, id, goal, self.planned[j], fb.position) {
                    self.event(Event::Fault(reason));
                }
            }
        }
        if self.state == State::Boot && self.all_known() {
            self.event(Event::BootDone);
        }
    }

    fn fault_servo(&mut self, joint: usize, id: u8, error: u8) {
        let reason = SafeReason::ServoError {
            joint: joint as u8,
            id,
            error,
        };
        let before = self.state;
        self.event(Event::Fault(reason));
        if before != self.state && error == 0 {
            // The alert says "a hardware error is latched"; which one is in register 70.
            self.hw_error_pending = Some(joint as u8);
        }
    }

    /// Queues the record of `plan`'s cycle if it is due: streaming cycles every
    /// `feedback_every` (proprioception), all others every `telemetry_every` (0 = none). The goals,
    /// clamp flags and setpoint come from the plan (what the cycle wrote), the positions from its
    /// replies, so the record holds together however late the link converts it.
    fn queue_telemetry(&mut self, plan: &CyclePlan, stats: &CycleStats) {
        let (every, countdown) = match plan.setpoint {
            Some(_) => (self.stream.feedback_every, &mut self.stream.countdown),
            None => (self.config.telemetry_every, &mut self.telemetry_countdown),
        };
        if every == 0 {
            return;
        }
        if *countdown > 1 {
            *countdown -= 1;
            return;
        }
        *countdown = every;
        let n = self.joints.len();
        let mut joints = [JointSample::default(); MAX_JOINTS];
        for (j, s) in joints.iter_mut().enumerate().take(n) {
            let fb = self.present[j];
            let mut f = self.reply_flags[j];
            if plan.clamped & (1 << j) != 0 {
                f |= flags::CLAMPED;
            }
            if !self.torque_sent {
                f |= flags::TORQUE_OFF;
            }
            if fb.alert {
                f |= flags::ALERT;
            }
            f |= self.health_flags(j);
            *s = JointSample {
                commanded: plan.goals().get(j).map_or(self.goals[j], |g| g.position),
                present: fb.position,
                velocity: fb.velocity,
                load: fb.load,
                error: match self.state {
                    State::Safe(SafeReason::ServoError { joint, error, .. })
                        if usize::from(joint) == j =>
                    {
                        error
                    }
                    _ => 0,
                },
                flags: f,
            };
        }
        let (step, slice) = self.playback().unwrap_or((0, 0));
        let record = Record {
            time_us: plan.start_us,
            cycle: self.counters.cycles,
            state: self.state,
            step,
            slice,
            setpoint: plan.setpoint,
            joint_count: n as u8,
            joints,
            cycle_us: stats.duration_us().min(u32::MAX as u64) as u32,
            timeouts: self.counters.timeouts,
            crc_errors: self.counters.crc_errors,
            overruns: self.counters.overruns,
            platform: self.platform_sample(plan),
            health: *self.health.readings(),
        };
        self.telemetry.push(record);
    }
}

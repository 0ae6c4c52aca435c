//! One bus cycle as the controller sees it: what to do on the bus next, and what to make of the
//! replies (feedback, misses, alerts, state events, telemetry).

use dynamixel::master::{BusError, CycleStats, Goal, Reply, ReplyFault};
use embedded_storage::nor_flash::NorFlash;

use super::Controller;
use crate::playback::{self, MAX_JOINTS, Ramp};
use crate::safety::{Event, SafeReason, State};
use crate::store::FlashWindow;
use crate::telemetry::{JointSample, Record, flags};

/// What the bus loop performs next.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum BusAction {
    /// Nothing to talk to (no joint map).
    Nothing,
    /// Sync Write the plan's goals, then Sync Read feedback.
    Cycle,
    /// Sync Read feedback only.
    ReadOnly,
    /// Sync Write the plan's goals (the present posture), then Torque Enable = 1 on all.
    TorqueOn,
    /// Torque Enable = 0 on all.
    TorqueOff,
    /// Reboot every servo (clears hardware errors; torque is off afterwards).
    Reboot,
    /// Read the Hardware Error Status of one joint's servo.
    ReadHardwareError { joint: u8 },
}

/// The next bus action with the goals it writes (`goals[..n]`, also the servos it reads).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CyclePlan {
    pub action: BusAction,
    pub goals: [Goal; MAX_JOINTS],
    pub n: usize,
    pub start_us: u64,
}

impl CyclePlan {
    pub fn goals(&self) -> &[Goal] {
        &self.goals[..self.n]
    }

    /// Bus IDs in joint order.
    pub fn ids(&self) -> ([u8; MAX_JOINTS], usize) {
        let mut ids = [0; MAX_JOINTS];
        for (i, g) in self.goals().iter().enumerate() {
            ids[i] = g.id;
        }
        (ids, self.n)
    }
}

/// What came of a bus action.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// A Cycle or ReadOnly: statistics (replies are passed alongside).
    Feedback(Result<CycleStats, BusError>),
    /// TorqueOn, TorqueOff, Reboot or Nothing.
    Done(Result<(), BusError>),
    /// ReadHardwareError: the status bits.
    HardwareError(Result<u8, BusError>),
}

/// Streaming mode: latest setpoint goals and their age.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct Stream {
    pub seq: u32,
    pub age: u16,
    pub timeout_cycles: u16,
    pub feedback_every: u16,
}

impl<F: NorFlash + FlashWindow> Controller<F> {
    /// Decides the next bus action at `now_us` (the cycle start) and advances ramp, gait clock and
    /// streaming by the time since the previous plan.
    pub fn plan(&mut self, now_us: u64) -> CyclePlan {
        let dt = match self.last_plan_us {
            Some(t) => now_us.saturating_sub(t).min(u32::MAX as u64) as u32,
            None => 0,
        };
        self.last_plan_us = Some(now_us);
        let action = self.next_action(dt);
        let (goals, n) = self.goal_list();
        CyclePlan {
            action,
            goals,
            n,
            start_us: now_us,
        }
    }

    fn next_action(&mut self, dt: u32) -> BusAction {
        if self.joints.is_empty() {
            if self.state == State::Boot {
                self.event(Event::BootDone);
            }
            return BusAction::Nothing;
        }
        if self.reboot_pending {
            return BusAction::Reboot;
        }
        if let Some(joint) = self.hw_error_pending {
            return BusAction::ReadHardwareError { joint };
        }
        if !self.state.drives_goals() {
            // Safe keeps whatever torque the servos have: the faulty one has dropped it already,
            // the others hold their last goal rather than letting the robot fall.
            let off = matches!(self.state, State::Idle | State::EStop);
            return if off && self.torque_sent {
                BusAction::TorqueOff
            } else {
                BusAction::ReadOnly
            };
        }
        if !self.torque_sent {
            if !self.all_known() {
                return BusAction::ReadOnly;
            }
            // Before torque comes on, the goals become the present posture, so nothing jumps.
            for j in 0..self.joints.len() {
                self.goals[j] = self.present[j].position;
            }
            return BusAction::TorqueOn;
        }
        match self.state {
            State::Ramping => self.ramp_goals(dt),
            State::Walking | State::Stopping => self.walk_goals(dt),
            State::Streaming => {
                self.stream.age = self.stream.age.saturating_add(1);
                if self.stream.age > self.stream.timeout_cycles {
                    self.event(Event::Fault(SafeReason::SetpointTimeout));
                    return BusAction::ReadOnly;
                }
            }
            _ => {}
        }
        BusAction::Cycle
    }

    fn ramp_goals(&mut self, dt: u32) {
        let Some(sel) = self.selected else { return };
        let n = self.joints.len();
        let mut target = [0i32; MAX_JOINTS];
        let Some(sample) = self.play.as_ref().map(|p| p.sample(sel.layout.slices)) else {
            return;
        };
        let Some(bytes) = self.store.table(sel.slot) else {
            return;
        };
        let view = crate::gait_view::View::new(bytes, sel.layout);
        let mut cut = [false; MAX_JOINTS];
        let clamped = playback::goals(
            &view,
            sample,
            &self.joints,
            &self.stiffness,
            &mut target[..n],
            &mut cut[..n],
        );
        self.count_clamped(clamped);
        let ramp = self.ramp.get_or_insert_with(|| {
            let mut from = [0i32; MAX_JOINTS];
            for (f, p) in from.iter_mut().zip(&self.present[..n]) {
                *f = p.position;
            }
            Ramp::new(
                &from[..n],
                &target[..n],
                self.config.ramp_ticks_per_s,
                self.config.ramp_min_us,
            )
        });
        let arrived = ramp.advance(dt);
        ramp.goals(&mut self.goals[..n]);
        if arrived {
            self.ramp = None;
            self.event(Event::RampDone);
        }
    }

    fn walk_goals(&mut self, dt: u32) {
        let Some(sel) = self.selected else { return };
        let Some(play) = self.play.as_mut() else {
            return;
        };
        let adv = play.advance(dt);
        if adv.finished {
            self.event(Event::StepsDone);
        } else if adv.steps_ended > 0 {
            if self.state == State::Stopping {
                play.rest_at_boundary();
            }
            self.event(Event::EndOfStep);
        }
        let Some(play) = self.play.as_ref() else {
            return;
        };
        let sample = play.sample(sel.layout.slices);
        let Some(bytes) = self.store.table(sel.slot) else {
            return;
        };
        let view = crate::gait_view::View::new(bytes, sel.layout);
        let n = self.joints.len();
        let mut goals = [0i32; MAX_JOINTS];
        let mut cut = [false; MAX_JOINTS];
        let clamped = playback::goals(
            &view,
            sample,
            &self.joints,
            &self.stiffness,
            &mut goals[..n],
            &mut cut[..n],
        );
        self.goals[..n].copy_from_slice(&goals[..n]);
        self.clamped = cut;
        self.count_clamped(clamped);
    }

    fn count_clamped(&mut self, n: usize) {
        self.counters.clamped = self.counters.clamped.wrapping_add(n as u32);
    }

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
        self.counters.cycles = self.counters.cycles.wrapping_add(1);
        self.counters.jitter_us = late_us;
        self.counters.max_jitter_us = self.counters.max_jitter_us.max(late_us);
        match (plan.action, outcome) {
            (BusAction::TorqueOn, Outcome::Done(Ok(()))) => self.torque_sent = true,
            (BusAction::TorqueOff, Outcome::Done(Ok(()))) => self.torque_sent = false,
            (BusAction::Reboot, Outcome::Done(r)) => {
                // Rebooted servos come back with torque off; Boot then looks for all of them.
                self.reboot_pending = false;
                self.torque_sent = false;
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
                    self.state = State::Safe(SafeReason::ServoError {
                        joint,
                        id,
                        error: bits,
                    });
                }
            }
            // No servos: the record still tells the host the board is alive and in which state.
            (BusAction::Nothing, _) => self.queue_telemetry(plan, &CycleStats::default()),
            (BusAction::Cycle | BusAction::ReadOnly, Outcome::Feedback(Ok(stats))) => {
                self.take_replies(plan, replies);
                self.queue_telemetry(plan, &stats);
            }
            (_, Outcome::Done(Err(_)) | Outcome::Feedback(Err(_))) => {
                self.counters.bus_errors = self.counters.bus_errors.wrapping_add(1);
            }
            _ => {}
        }
    }

    fn take_replies(&mut self, plan: &CyclePlan, replies: &[Reply]) {
        let n = self.joints.len().min(plan.n).min(replies.len());
        for (j, reply) in replies.iter().enumerate().take(n) {
            let id = self.joints[j].id;
            let usable = match reply {
                Ok(fb) => {
                    self.present[j] = *fb;
                    self.known[j] = true;
                    if fb.alert {
                        self.fault_servo(j, id, 0);
                    }
                    true
                }
                Err(ReplyFault::Status(e)) => {
                    // A servo that answers with an error number is there, but its data is not.
                    self.fault_servo(j, id, e.0);
                    true
                }
                Err(ReplyFault::Timeout) => {
                    self.counters.timeouts = self.counters.timeouts.wrapping_add(1);
                    false
                }
                Err(ReplyFault::Crc) => {
                    self.counters.crc_errors = self.counters.crc_errors.wrapping_add(1);
                    false
                }
                Err(_) => false,
            };
            if let Some(reason) = self.misses.record(j, id, usable) {
                self.event(Event::Fault(reason));
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

    fn queue_telemetry(&mut self, plan: &CyclePlan, stats: &CycleStats) {
        if self.config.telemetry_every == 0 {
            return;
        }
        if self.telemetry_countdown > 1 {
            self.telemetry_countdown -= 1;
            return;
        }
        self.telemetry_countdown = self.config.telemetry_every;
        let n = self.joints.len();
        let mut joints = [JointSample::default(); MAX_JOINTS];
        for (j, s) in joints.iter_mut().enumerate().take(n) {
            let fb = self.present[j];
            let mut f = 0;
            if self.clamped[j] {
                f |= flags::CLAMPED;
            }
            if !self.torque_sent {
                f |= flags::TORQUE_OFF;
            }
            if fb.alert {
                f |= flags::ALERT;
            }
            *s = JointSample {
                commanded: self.goals[j],
                present: fb.position,
                velocity: fb.velocity,
                load: fb.load,
                error: 0,
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
            joint_count: n as u8,
            joints,
            cycle_us: stats.duration_us().min(u32::MAX as u64) as u32,
            timeouts: self.counters.timeouts,
            crc_errors: self.counters.crc_errors,
            overruns: self.counters.overruns,
        };
        self.telemetry.push(record);
    }

    /// Records cycle starts the bus loop missed.
    pub fn count_overruns(&mut self, missed: u32) {
        self.counters.overruns = self.counters.overruns.wrapping_add(missed);
    }

    /// Applies `event` to the state machine and does what entering the new state requires.
    /// Refused events change nothing.
    pub(crate) fn event(&mut self, event: Event) -> bool {
        let Ok(next) = self.state.next(event) else {
            return false;
        };
        let before = self.state;
        self.state = next;
        if before != next {
            self.enter(before, next);
        }
        true
    }

    fn enter(&mut self, _from: State, to: State) {
        match to {
            State::Idle | State::EStop => self.ramp = None,
            State::Boot => {
                self.misses.reset();
                self.known = [false; MAX_JOINTS];
                self.ramp = None;
            }
            State::Standing | State::Streaming => {
                self.ramp = None;
                self.stream.age = 0;
            }
            State::Ramping => self.ramp = None,
            State::Safe(_) => self.ramp = None,
            State::Walking | State::Stopping => {}
        }
    }
}

//! One bus cycle as the controller sees it: what to do on the bus next (ramp, gait clock, streaming,
//! torque, the servos' P gains) and the state machine events that move it; `feedback.rs` takes the
//! results.

use dynamixel::master::{BusError, CycleStats, Goal};
use dynamixel::units::p_gain_for_stiffness;
use embedded_storage::nor_flash::NorFlash;

use super::Controller;
use crate::gait_view::View;
use crate::playback::{MAX_JOINTS, Ramp, RampGroup, start_lifts};
use crate::safety::{Event, SafeReason, State};
use crate::store::FlashWindow;
use crate::telemetry::SetpointStamp;

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
    /// Sync Write the plan's goals (the present posture), then the Position P Gains
    /// ([`CyclePlan::gains`]), then Torque Enable = 1 on all.
    TorqueOn,
    /// Sync Write the Position P Gains ([`CyclePlan::gains`]), then as `Cycle`: issued once, when a
    /// joint's stiffness or the selected gait changed while torque is on (again on the next cycle if
    /// it fails).
    WriteGains,
    /// Torque Enable = 0 on all.
    TorqueOff,
    /// Reboot the servos of the joints in the mask (bit j = joint j; clears hardware errors,
    /// their torque is off afterwards).
    Reboot { joints: u32 },
    /// Read the Hardware Error Status of one joint's servo.
    ReadHardwareError { joint: u8 },
    /// Check the perturbation platform's servo `id` once it is set up: ping it, write its Profile
    /// Velocity and its Goal Position `rest`, read its Present Position, and with `torque` (the
    /// joints hold torque) switch its torque on.
    PlatformCheck {
        id: u8,
        profile_velocity: u16,
        rest: u16,
        torque: bool,
    },
}

/// The next bus action with the goals it writes (`goals[..n]`, also the servos it reads).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CyclePlan {
    pub action: BusAction,
    pub goals: [Goal; MAX_JOINTS],
    pub n: usize,
    pub start_us: u64,
    /// Joints whose goal was clamped to a limit (bit j), as planned.
    pub clamped: u32,
    /// A streaming cycle: the setpoint its Sync Write carries. Taken with the goals, because a
    /// setpoint arriving during the bus transaction changes the controller's goals and sequence
    /// number before the cycle completes (and before the link converts its record).
    pub setpoint: Option<SetpointStamp>,
    /// TorqueOn and WriteGains: each joint's Position P Gain register value for its stiffness
    /// (`dynamixel::units::p_gain_for_stiffness`); 0 = stiffness 0 (torque bias off): that servo's
    /// gain is left as it is, never set to a limp 0.
    pub gains: [u16; MAX_JOINTS],
    /// The stiffness settings the gains come from (a change during the bus action makes them stale).
    pub gain_gen: u32,
    /// The perturbation platform's servo and goal, while a checked platform is set up: it rides
    /// in the joints' goal Sync Write (and Sync Read) after them, and in their torque switches.
    pub platform: Option<Goal>,
    /// `(joint, bus ID)` whose Present Input Voltage and Present Temperature the bus loop reads
    /// after the action, if the cycle leaves time for it before the next start
    /// ([`crate::bus_loop`]); one servo per cycle in turn.
    pub health_read: Option<(u8, u8)>,
    /// The host's servo read ([`Controller::read_servo`]), done after the action if the cycle
    /// leaves time for it; it waits for a later cycle otherwise.
    pub servo_read: Option<protocol::ServoRead>,
}

impl CyclePlan {
    pub fn goals(&self) -> &[Goal] {
        &self.goals[..self.n]
    }

    /// `(id, P gain)` of the joints whose gain the plan writes (stiffness not 0).
    pub fn gain_writes(&self) -> impl Iterator<Item = (u8, u16)> + '_ {
        self.goals()
            .iter()
            .zip(&self.gains)
            .filter(|(_, p)| **p != 0)
            .map(|(g, p)| (g.id, *p))
    }

    /// The goals a goal Sync Write carries: the joints' and, last, the platform's. There is room:
    /// a platform is refused beside a full joint map.
    pub fn goals_with_platform(&self) -> ([Goal; MAX_JOINTS], usize) {
        let mut all = self.goals;
        match self.platform {
            Some(g) if self.n < MAX_JOINTS => {
                all[self.n] = g;
                (all, self.n + 1)
            }
            _ => (all, self.n),
        }
    }

    /// Replies a bus action reads: one per joint, and the platform's after them in a goal cycle.
    pub fn reply_count(&self) -> usize {
        match self.action {
            BusAction::Cycle | BusAction::WriteGains => self.goals_with_platform().1,
            _ => self.n,
        }
    }

    /// Bus IDs whose torque a switch addresses: the joints' and the platform's.
    pub fn torque_ids(&self) -> ([u8; MAX_JOINTS], usize) {
        let (goals, n) = self.goals_with_platform();
        let mut ids = [0; MAX_JOINTS];
        for (i, g) in ids.iter_mut().zip(&goals[..n]) {
            *i = g.id;
        }
        (ids, n)
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
    /// A Cycle, ReadOnly or WriteGains: statistics (replies are passed alongside).
    Feedback(Result<CycleStats, BusError>),
    /// TorqueOn, TorqueOff, Reboot or Nothing. (WriteGains gives `Feedback`: its gain write failing
    /// is `Feedback(Err)` without the cycle.)
    Done(Result<(), BusError>),
    /// ReadHardwareError: the status bits.
    HardwareError(Result<u8, BusError>),
    /// PlatformCheck: the platform servo's present position, ticks.
    PlatformChecked(Result<u16, BusError>),
}

/// Streaming mode: latest setpoint goals and their age.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct Stream {
    /// The last setpoint's goals and their planned angles (no bias), ticks: the goals move toward
    /// them by at most the servo's step per cycle ([`crate::goal_step`]).
    pub target: [i32; MAX_JOINTS],
    pub planned_target: [i32; MAX_JOINTS],
    pub seq: u32,
    pub age: u16,
    pub timeout_cycles: u16,
    pub feedback_every: u16,
    /// Cycles until the next proprioception record.
    pub countdown: u16,
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
        self.flash_ops_at_plan = self.flash_ops;
        let action = self.next_action(dt);
        let platform = self.platform_goal(action);
        let health_read = self.health_read_for(action);
        let (goals, n) = self.goal_list();
        let clamped = (0..n.min(32))
            .filter(|&j| self.clamped[j])
            .fold(0u32, |m, j| m | 1 << j);
        let writes_goals = matches!(action, BusAction::Cycle | BusAction::WriteGains);
        let setpoint = (self.state == State::Streaming && writes_goals).then_some(SetpointStamp {
            seq: self.stream.seq,
            age: self.stream.age,
        });
        CyclePlan {
            action,
            goals,
            n,
            start_us: now_us,
            clamped,
            setpoint,
            gains: self.gain_list(action),
            gain_gen: self.gains_wanted,
            platform,
            health_read,
            servo_read: self.servo_read,
        }
    }

    /// The P gains a TorqueOn or WriteGains writes (all 0 for other actions).
    fn gain_list(&self, action: BusAction) -> [u16; MAX_JOINTS] {
        let mut gains = [0; MAX_JOINTS];
        if matches!(action, BusAction::TorqueOn | BusAction::WriteGains) {
            for ((p, j), &k) in gains.iter_mut().zip(&self.joints).zip(&self.stiffness) {
                *p = p_gain_for_stiffness(j.model, k as f32 / 1000.0);
            }
        }
        gains
    }

    /// Whether the servos' P gains are behind the stiffness settings. Settings that are all 0
    /// (bias off everywhere) write nothing, so they count as written.
    fn gains_due(&mut self) -> bool {
        if self.gains_written == self.gains_wanted {
            return false;
        }
        if self.stiffness[..self.joints.len()].iter().all(|&k| k == 0) {
            self.gains_written = self.gains_wanted;
            return false;
        }
        true
    }

    fn next_action(&mut self, dt: u32) -> BusAction {
        if let Some(check) = self.platform_check_due() {
            // Set up only when not moving: one cycle of the standing posture's writes is skipped.
            return check;
        }
        if self.joints.is_empty() {
            if self.state == State::Boot {
                self.event(Event::BootDone);
            }
            return BusAction::Nothing;
        }
        if let Some(joints) = self.reboot_pending {
            return BusAction::Reboot { joints };
        }
        if let Some(joint) = self.hw_error_pending {
            return BusAction::ReadHardwareError { joint };
        }
        if !self.state.drives_goals() {
            // Safe keeps whatever torque the servos have: the faulty one has dropped it already,
            // the others hold their last goal rather than letting the robot fall.
            let off = matches!(self.state, State::Idle | State::EStop);
            return if off && (self.torque_sent || self.torque_unknown) {
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
                self.planned[j] = self.goals[j];
            }
            return BusAction::TorqueOn;
        }
        match self.state {
            State::Ramping => self.ramp_goals(dt),
            State::Walking => {
                self.check_host();
                self.walk_goals(dt);
            }
            State::Stopping => self.walk_goals(dt),
            State::Streaming => {
                self.stream.age = self.stream.age.saturating_add(1);
                if self.stream.age > self.stream.timeout_cycles {
                    self.event(Event::Fault(SafeReason::SetpointTimeout));
                    return BusAction::ReadOnly;
                }
                self.stream_goals();
            }
            _ => {}
        }
        if self.gains_due() {
            BusAction::WriteGains
        } else {
            BusAction::Cycle
        }
    }

    /// The host-loss rule: an endless run whose host has been silent for
    /// `host_timeout_cycles` cycles stops at the end of the step (finite runs end by themselves).
    fn check_host(&mut self) {
        let limit = self.config.host_timeout_cycles;
        let endless = self.play.as_ref().is_some_and(|p| p.endless()) || self.queue_endless();
        if limit == 0 || !endless {
            return;
        }
        self.host_quiet = self.host_quiet.saturating_add(1);
        if self.host_quiet > limit && self.event(Event::Stop) {
            self.counters.host_lost = self.counters.host_lost.wrapping_add(1);
        }
    }

    /// The per-cycle goal step of `joint` ([`crate::goal_step::max_step_ticks`]).
    fn step_ticks(&self, joint: usize) -> i32 {
        crate::goal_step::max_step_ticks(self.joints[joint].model, self.config.cycle_hz)
    }

    /// Streaming: each goal moves toward the last setpoint by at most the servo's step this cycle
    /// (a setpoint far away is approached at the servo's no-load speed, never jumped to).
    fn stream_goals(&mut self) {
        let mut limited = 0u32;
        for j in 0..self.joints.len() {
            let step = self.step_ticks(j);
            let (g, cut) = crate::goal_step::toward(self.goals[j], self.stream.target[j], step);
            self.goals[j] = g;
            self.planned[j] =
                crate::goal_step::toward(self.planned[j], self.stream.planned_target[j], step).0;
            limited += cut as u32;
        }
        self.counters.rate_limited = self.counters.rate_limited.wrapping_add(limited);
    }

    /// Walking: a stiffness change moves the torque bias, which would step the goals by
    /// torque x (1/k_new - 1/k_old). At the first cycle after a change the difference between the
    /// goals with the stiffness the bias had and with the new one becomes a residual added to
    /// the new goals (so that cycle's goals are where the old bias had them), and the residual
    /// shrinks toward 0 by at most the servo's step per cycle ([`crate::goal_step`]).
    fn follow_stiffness(&mut self, sample: crate::playback::Sample, goals: &mut [i32]) {
        let n = goals.len();
        if self.bias_k[..n] != self.stiffness[..n] {
            let old_k = self.bias_k;
            let mut old = [0i32; MAX_JOINTS];
            let mut cut = [false; MAX_JOINTS];
            if self
                .sample_goals(sample, &old_k[..n], &mut old[..n], &mut cut[..n])
                .is_some()
            {
                for ((r, o), g) in self.bias_residual.iter_mut().zip(&old[..n]).zip(&*goals) {
                    *r += o - g;
                }
            }
            self.bias_k[..n].copy_from_slice(&self.stiffness[..n]);
        }
        let mut limited = 0u32;
        for (j, g) in goals.iter_mut().enumerate() {
            if self.bias_residual[j] == 0 {
                continue;
            }
            let (r, cut) = crate::goal_step::toward(self.bias_residual[j], 0, self.step_ticks(j));
            // The residual this cycle still carries is the one before the step: the change's
            // first cycle keeps the old bias's goals exactly.
            let carried = self.bias_residual[j];
            self.bias_residual[j] = r;
            let cal = &self.joints[j];
            *g = (*g + carried).clamp(cal.min_ticks, cal.max_ticks);
            limited += cut as u32;
        }
        self.counters.rate_limited = self.counters.rate_limited.wrapping_add(limited);
    }

    fn ramp_goals(&mut self, dt: u32) {
        let Some(sel) = self.selected else { return };
        let n = self.joints.len();
        let mut target = [0i32; MAX_JOINTS];
        let Some(sample) = self.play.as_ref().map(|p| p.sample(sel.layout.slices)) else {
            return;
        };
        let mut cut = [false; MAX_JOINTS];
        let Some(clamped) =
            self.sample_goals(sample, &self.stiffness, &mut target[..n], &mut cut[..n])
        else {
            return;
        };
        self.count_clamped(clamped);
        if self.ramp.is_none() {
            // The ramp's target has the bias of these settings: a change from here on is
            // followed from the walk's first cycle (`follow_stiffness`).
            self.bias_k = self.stiffness;
            self.bias_residual = [0; MAX_JOINTS];
        }
        if self.ramp.is_none() {
            let mut from = [0i32; MAX_JOINTS];
            for (f, p) in from.iter_mut().zip(&self.present[..n]) {
                *f = p.position;
            }
            let mut lift = [0i32; MAX_JOINTS];
            let mut group = [RampGroup::Whole; MAX_JOINTS];
            if let Some(bytes) = self.store.table(sel.slot) {
                let view = View::new(bytes, sel.layout);
                start_lifts(&view, &self.joints, &mut lift[..n], &mut group[..n]);
            }
            self.ramp = Some(Ramp::stepping(
                &from[..n],
                &target[..n],
                &lift[..n],
                &group[..n],
                self.config.ramp_ticks_per_s,
                self.config.ramp_min_us,
            ));
        }
        let Some(ramp) = self.ramp.as_mut() else {
            return;
        };
        let arrived = ramp.advance(dt);
        ramp.goals(&mut self.goals[..n]);
        for (g, cal) in self.goals[..n].iter_mut().zip(&self.joints) {
            *g = (*g).clamp(cal.min_ticks, cal.max_ticks);
        }
        // The ramp has no load plan of its own: the servo is meant to reach the goal itself.
        self.planned[..n].copy_from_slice(&self.goals[..n]);
        if arrived {
            self.ramp = None;
            self.event(Event::RampDone);
        }
    }

    fn walk_goals(&mut self, dt: u32) {
        let Some(play) = self.play.as_mut() else {
            return;
        };
        let adv = play.advance(dt);
        let boundary = adv.finished || (adv.steps_ended > 0 && play.endless());
        let stopping = self.state == State::Stopping;
        if adv.steps_ended > 0 && stopping && !adv.finished {
            play.rest_at_boundary();
        }
        if adv.steps_ended > 0 {
            self.steer_at_boundary();
        }
        if boundary && self.switch_at_boundary() {
            // The queued gait took over at this boundary; its clock starts at its slice 0.
        } else if adv.finished {
            self.event(Event::StepsDone);
        } else if adv.steps_ended > 0 {
            self.event(Event::EndOfStep);
        }
        // After a switch, the new gait's table and clock.
        let Some(sel) = self.selected else { return };
        let Some(play) = self.play.as_ref() else {
            return;
        };
        let sample = play.sample(sel.layout.slices);
        let n = self.joints.len();
        let mut goals = [0i32; MAX_JOINTS];
        let mut cut = [false; MAX_JOINTS];
        let Some(clamped) =
            self.sample_goals(sample, &self.stiffness, &mut goals[..n], &mut cut[..n])
        else {
            return;
        };
        // The same sample without the torque bias (stiffness 0 switches it off): what a servo
        // carrying the planned load reaches. Its clamp count is the biased goal's business.
        let mut planned = [0i32; MAX_JOINTS];
        let mut planned_cut = [false; MAX_JOINTS];
        self.sample_goals(
            sample,
            &[0; MAX_JOINTS][..n],
            &mut planned[..n],
            &mut planned_cut[..n],
        );
        self.follow_stiffness(sample, &mut goals[..n]);
        self.goals[..n].copy_from_slice(&goals[..n]);
        self.planned[..n].copy_from_slice(&planned[..n]);
        self.clamped = cut;
        self.count_clamped(clamped);
    }

    fn count_clamped(&mut self, n: usize) {
        self.counters.clamped = self.counters.clamped.wrapping_add(n as u32);
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
        crate::device_log::transition(before, next, crate::device_log::Cause::Event(event));
        if before != next {
            self.enter(before, next);
        }
        true
    }

    fn enter(&mut self, from: State, to: State) {
        match to {
            State::Idle if matches!(from, State::Safe(_) | State::EStop) => {
                // ClearFault: the host says the cause is gone, so the miss limit starts afresh. A
                // servo that had run up its misses would otherwise fault again on its first lost
                // reply, e.g. one of the Sync Read that was in flight when the command came.
                self.ramp = None;
                self.misses.reset();
                self.stuck.reset();
            }
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
            State::Stopping => {}
            State::Walking => {}
        }
        if !matches!(to, State::Ramping | State::Walking) {
            // Stopping, a fault, a lost host: nothing waits to walk on afterwards.
            self.queue.clear();
        }
        if !matches!(to, State::Ramping | State::Walking | State::Stopping) {
            // The steered walk ends with its last step (Stopping still plays the blend).
            self.steer = None;
        }
    }
}

//! The controller driven cycle by cycle against ideal servos (they reach every goal at once), on a
//! NOR double and a hand-advanced clock: boot, ramp, walk, stop at the step end, faults, uploads.

use dynamixel::instruction::StatusError;
use dynamixel::master::{BusError, CycleStats, Feedback, Reply, ReplyFault};

use super::*;
use crate::playback::Direction;
use crate::safety::SafeReason;
use crate::store::nor_double::NorDouble;
use crate::store::record::CRC32;
use crate::testkit::{JOINTS, STIFFNESS, SyntheticGait};

mod platform;
mod reupload;
mod steer;
mod switch;

type Flash = NorDouble<4>;

/// 22 servos that are wherever their goal is once torque is on.
struct IdealServos {
    pos: [i32; 32],
    torque: bool,
    /// Joints that do not answer.
    silent: Vec<usize>,
    /// Joint whose status carries the Alert bit.
    alert: Option<usize>,
    /// Joints whose output is jammed: they answer but do not move.
    stuck: Vec<usize>,
    torque_writes: Vec<bool>,
    reboots: usize,
    /// Position P Gain register per joint (850: the servo's default), and how many gain writes
    /// fail before one succeeds.
    p_gain: [u16; 32],
    fail_gain_writes: usize,
    /// The perturbation platform's servo: whether it answers, where it is (it reaches its goal
    /// at once), its torque, and the goal each goal Sync Write carried for it (`None`: none).
    platform_answers: bool,
    platform_pos: i32,
    platform_torque: bool,
    platform_goals: Vec<Option<i32>>,
}

impl IdealServos {
    fn new() -> Self {
        let mut pos = [0; 32];
        for (j, p) in pos.iter_mut().enumerate() {
            *p = 1800 + 23 * j as i32;
        }
        Self {
            pos,
            torque: false,
            silent: vec![],
            alert: None,
            stuck: vec![],
            torque_writes: vec![],
            reboots: 0,
            p_gain: [850; 32],
            fail_gain_writes: 0,
            platform_answers: true,
            platform_pos: 2047,
            platform_torque: false,
            platform_goals: vec![],
        }
    }

    fn serve(&mut self, plan: &CyclePlan, replies: &mut [Reply]) -> Outcome {
        let feedback = |s: &Self, replies: &mut [Reply]| {
            for (j, r) in replies.iter_mut().enumerate().take(plan.n) {
                *r = if s.silent.contains(&j) {
                    Err(ReplyFault::Timeout)
                } else {
                    Ok(Feedback {
                        load: 0,
                        velocity: 0,
                        position: s.pos[j],
                        alert: s.alert == Some(j),
                    })
                };
            }
            Outcome::Feedback(Ok(CycleStats::default()))
        };
        if matches!(plan.action, BusAction::TorqueOn | BusAction::WriteGains) {
            if self.fail_gain_writes > 0 {
                self.fail_gain_writes -= 1;
                let e = BusError::Io(embedded_io_async::ErrorKind::TimedOut);
                return match plan.action {
                    BusAction::TorqueOn => Outcome::Done(Err(e)),
                    _ => Outcome::Feedback(Err(e)),
                };
            }
            for (id, p) in plan.gain_writes() {
                self.p_gain[usize::from(id) - 1] = p;
            }
        }
        match plan.action {
            BusAction::Nothing => Outcome::Done(Ok(())),
            BusAction::Cycle | BusAction::WriteGains => {
                if self.torque {
                    for (j, g) in plan.goals().iter().enumerate() {
                        if !self.stuck.contains(&j) {
                            self.pos[j] = g.position;
                        }
                    }
                }
                self.platform_goals.push(plan.platform.map(|g| g.position));
                if let Some(g) = plan.platform {
                    if self.platform_torque {
                        self.platform_pos = g.position;
                    }
                    replies[plan.n] = if self.platform_answers {
                        Ok(Feedback {
                            load: 0,
                            velocity: 0,
                            position: self.platform_pos,
                            alert: false,
                        })
                    } else {
                        Err(ReplyFault::Timeout)
                    };
                }
                feedback(self, replies)
            }
            BusAction::ReadOnly => feedback(self, replies),
            BusAction::TorqueOn => {
                // The goals written before torque-on are the present posture: nothing moves.
                for (j, g) in plan.goals().iter().enumerate() {
                    assert_eq!(g.position, self.pos[j], "joint {j} would jump at torque-on");
                }
                self.torque = true;
                self.platform_torque |= plan.platform.is_some();
                self.torque_writes.push(true);
                Outcome::Done(Ok(()))
            }
            BusAction::TorqueOff => {
                self.torque = false;
                self.platform_torque &= plan.platform.is_none();
                self.torque_writes.push(false);
                Outcome::Done(Ok(()))
            }
            BusAction::Reboot { joints } => {
                self.torque = false;
                if self.alert.is_some_and(|j| joints & (1 << j) != 0) {
                    self.alert = None;
                }
                self.reboots += joints.count_ones().min(JOINTS as u32) as usize;
                Outcome::Done(Ok(()))
            }
            BusAction::ReadHardwareError { .. } => Outcome::HardwareError(Ok(0x20)),
            BusAction::PlatformCheck { rest, torque, .. } => {
                if !self.platform_answers {
                    return Outcome::PlatformChecked(Err(BusError::Reply {
                        id: 23,
                        fault: ReplyFault::Timeout,
                    }));
                }
                let present = self.platform_pos as u16;
                self.platform_pos = i32::from(rest);
                self.platform_torque = torque;
                Outcome::PlatformChecked(Ok(present))
            }
        }
    }
}

/// Uploads `table` into `slot` in one chunk; every step must be accepted.
fn upload(c: &mut Controller<Flash>, slot: u8, table: &[u8]) {
    c.upload_begin(slot, table.len() as u32).unwrap();
    c.upload_chunk(0, table).unwrap();
    c.upload_commit(CRC32.checksum(table)).unwrap();
}

/// The default configuration with an endless run stopped after `cycles` cycles without the host.
fn host_timeout(cycles: u32) -> Config {
    Config {
        host_timeout_cycles: cycles,
        ..Config::default()
    }
}

struct Rig {
    c: Controller<Flash>,
    servos: IdealServos,
    now: u64,
    gait: SyntheticGait,
}

impl Rig {
    /// A board whose slot 0 holds the synthetic gait (100 slices, 1 s), booted at 100 Hz.
    fn new() -> Self {
        Self::with_config(Config::default())
    }

    fn with_config(config: Config) -> Self {
        let gait = SyntheticGait::new(100, 1.0);
        let table = gait.build();
        let mut c = Controller::new(Flash::new(64), 4, config);
        upload(&mut c, 0, &table);
        // Power cycle: the joint map comes from the stored table.
        let c = Controller::new(c.into_flash(), 4, config);
        assert_eq!(c.joints().len(), JOINTS);
        Self {
            c,
            servos: IdealServos::new(),
            now: 1_000_000,
            gait,
        }
    }

    /// The board booted: the first cycle reads every servo and the board is Idle.
    fn idle() -> Self {
        Self::idle_with(Config::default())
    }

    fn idle_with(config: Config) -> Self {
        let mut r = Self::with_config(config);
        assert_eq!(r.cycle(), BusAction::ReadOnly);
        assert_eq!(r.c.state(), State::Idle);
        r
    }

    /// Idle, after the one Torque Off of a fresh boot (torque state unknown after a reset).
    fn idle_torque_off() -> Self {
        let mut r = Self::idle();
        assert_eq!(r.cycle(), BusAction::TorqueOff);
        r
    }

    /// Idle, then slot 0 played without end and walked past its ramp.
    fn walking() -> Self {
        Self::walking_with(Config::default())
    }

    fn walking_with(config: Config) -> Self {
        let mut r = Self::idle_with(config);
        r.play(None);
        r.until(2000, State::Walking);
        r
    }

    fn cycle(&mut self) -> BusAction {
        self.cycle_with(|_, _, _| {})
    }

    /// One cycle in which `between` runs after the servos have answered and before the
    /// controller takes their replies: a command or flash work of the link task arriving while
    /// the bus task awaits the Sync Read.
    fn cycle_with(
        &mut self,
        between: impl FnOnce(&mut Controller<Flash>, &CyclePlan, &[Reply]),
    ) -> BusAction {
        let plan = self.c.plan(self.now);
        let mut replies = [Err(ReplyFault::Timeout); 32];
        let outcome = self.servos.serve(&plan, &mut replies);
        between(&mut self.c, &plan, &replies);
        self.c
            .complete(&plan, outcome, &replies[..plan.reply_count()], 0);
        self.now += u64::from(self.c.period_us());
        plan.action
    }

    /// The next cycle planned, and completed as a Sync Read whose replies are `replies` instead
    /// of the servos' own.
    fn complete_with(&mut self, replies: &[Reply]) {
        let plan = self.c.plan(self.now);
        self.c.complete(
            &plan,
            Outcome::Feedback(Ok(CycleStats::default())),
            replies,
            0,
        );
    }

    fn cycles_until(&mut self, max: usize, done: impl Fn(&Self) -> bool) -> usize {
        for i in 0..max {
            if done(self) {
                return i;
            }
            self.cycle();
        }
        panic!("not done after {max} cycles, state {:?}", self.c.state());
    }

    /// Cycles until the board is in `state`; the cycles run (panics after `max`).
    fn until(&mut self, max: usize, state: State) -> usize {
        self.cycles_until(max, |r| r.c.state() == state)
    }

    fn try_play(&mut self, steps: Option<u32>) -> Result<(), CommandError> {
        self.c.play(forward(0, steps))
    }

    fn play(&mut self, steps: Option<u32>) {
        self.try_play(steps).unwrap();
    }

    /// Cycles while the board walks; after every cycle that leaves it walking, each joint must be
    /// within a tick of `gait`'s goal (testkit formula) at the play clock, which advanced one
    /// 10 ms cycle. Returns the cycles run, the one that ended the walk included.
    fn walk_checking_goals(&mut self, gait: &SyntheticGait) -> usize {
        let period_us = (gait.period_s * 1e6).round() as u32;
        let mut cycles = 0;
        while self.c.state() == State::Walking {
            let t_before = self.c.play_clock().unwrap().phase_us();
            self.cycle();
            cycles += 1;
            if self.c.state() != State::Walking {
                break;
            }
            let (_, slice) = self.c.playback().unwrap();
            assert!(
                usize::from(slice) < gait.slices,
                "cycle {cycles}: slice {slice} of a {}-slice table",
                gait.slices
            );
            let t = (t_before + 10_000) % period_us;
            let pos = t as f64 / period_us as f64 * gait.slices as f64;
            for j in 0..JOINTS {
                let want = gait.goal(pos, j, STIFFNESS);
                assert!(
                    (self.servos.pos[j] as f64 - want).abs() <= 1.0,
                    "cycle {cycles} joint {j}: {} vs {want:.2}",
                    self.servos.pos[j]
                );
            }
        }
        cycles
    }
}

/// Slot `slot` played forward at its table's own period.
fn forward(slot: u8, steps: Option<u32>) -> PlayParams {
    PlayParams {
        slot,
        direction: Direction::Forward,
        period_scale: 1000,
        steps,
    }
}

/// Safe because `joint`'s servo (ID `joint + 1`, testkit) reported the hardware error `error`.
fn servo_error(joint: u8, error: u8) -> State {
    State::Safe(SafeReason::ServoError {
        joint,
        id: joint + 1,
        error,
    })
}

/// Safe because `joint`'s servo (ID `joint + 1`, testkit) missed three replies in a row, the
/// default miss limit.
fn servo_missing(joint: u8) -> State {
    State::Safe(SafeReason::ServoMissing {
        joint,
        id: joint + 1,
        cycles: 3,
    })
}

#[test]
fn boot_ramp_walk_and_stop_exactly_at_the_end_of_the_last_step() {
    let mut r = Rig::new();
    assert_eq!(r.c.state(), State::Boot);
    assert_eq!(r.cycle(), BusAction::ReadOnly);
    assert_eq!(r.c.state(), State::Idle);
    r.play(Some(2));
    assert_eq!(r.c.state(), State::Ramping);
    assert_eq!(r.cycle(), BusAction::TorqueOn);
    // Ramp: straight to slice 0 at 400 ticks/s for the joint with the longest way.
    let start: Vec<i32> = r.servos.pos[..JOINTS].to_vec();
    let target: Vec<f64> = (0..JOINTS)
        .map(|j| r.gait.goal(0.0, j, STIFFNESS))
        .collect();
    let longest = (0..JOINTS)
        .map(|j| (target[j] - start[j] as f64).abs())
        .fold(0.0, f64::max);
    let ramp_cycles = r.until(2000, State::Walking);
    let expected = (longest / 400.0 / 0.01).max(50.0);
    assert!(
        (ramp_cycles as f64 - expected).abs() <= 2.0,
        "ramp took {ramp_cycles} cycles, expected about {expected:.1}"
    );
    for (j, t) in target.iter().enumerate() {
        assert!(
            (r.servos.pos[j] as f64 - t).abs() <= 1.0,
            "joint {j} after the ramp"
        );
    }
    // Walking: every cycle's goals are the table interpolated at the gait clock, biased.
    let gait = r.gait.clone();
    let cycles = r.walk_checking_goals(&gait);
    // Two steps of 1 s at 100 Hz: the 200th cycle of the walk ends the second step.
    assert_eq!(cycles, 200);
    assert_eq!(r.c.state(), State::Standing);
    assert_eq!(r.c.playback().unwrap().0, 2);
    for (j, t) in target.iter().enumerate() {
        assert!(
            (r.servos.pos[j] as f64 - t).abs() <= 1.0,
            "joint {j} at rest"
        );
    }
    // Standing holds.
    let held: Vec<i32> = r.servos.pos[..JOINTS].to_vec();
    r.cycle();
    assert_eq!(&r.servos.pos[..JOINTS], &held[..]);
}

#[test]
fn stop_mid_step_finishes_the_step_first() {
    let mut r = Rig::walking();
    for _ in 0..30 {
        r.cycle();
    }
    r.c.stop().unwrap();
    assert_eq!(r.c.state(), State::Stopping);
    let n = r.until(200, State::Standing);
    // 30 cycles were played, so the step ends 70 cycles later.
    assert_eq!(n, 70);
    assert_eq!(r.c.play_clock().unwrap().phase_us(), 0);
}

#[test]
fn backward_play_runs_the_slices_in_reverse() {
    let mut r = Rig::idle();
    r.c.play(PlayParams {
        direction: Direction::Backward,
        period_scale: 2000,
        ..forward(0, Some(1))
    })
    .unwrap();
    r.until(2000, State::Walking);
    r.cycle();
    // One cycle of 10 ms at half speed is 5 ms of the table backward: slice position 99.5.
    for j in 0..JOINTS {
        let want = r.gait.goal(99.5, j, STIFFNESS);
        assert!((r.servos.pos[j] as f64 - want).abs() <= 1.0, "joint {j}");
    }
    // A whole step at half speed takes 200 cycles.
    let n = r.until(400, State::Standing);
    assert_eq!(n + 1, 200);
}

#[test]
fn stiffness_changed_while_walking_applies_from_the_next_cycle_without_a_step() {
    let mut r = Rig::walking();
    r.c.set_stiffness(4, 0).unwrap();
    let t = r.c.play_clock().unwrap().phase_us() + 10_000;
    // The change's first cycle keeps the bias joint 4 had (the goals do not step) ...
    r.cycle();
    let pos = t as f64 / 1e6 * 100.0;
    assert!((r.servos.pos[4] as f64 - r.gait.goal(pos, 4, STIFFNESS)).abs() <= 1.0);
    assert!((r.servos.pos[5] as f64 - r.gait.goal(pos, 5, STIFFNESS)).abs() <= 1.0);
    // ... and the next one has none: the bias it drops is at most 0.3 N m / 8.4 N m/rad =
    // 0.0357 rad = 23.3 ticks, within one MX-28 step (37 ticks at 100 Hz).
    r.cycle();
    let pos = (t + 10_000) as f64 / 1e6 * 100.0;
    assert!((r.servos.pos[4] as f64 - r.gait.goal(pos, 4, 0.0)).abs() <= 1.0);
    assert!((r.servos.pos[5] as f64 - r.gait.goal(pos, 5, STIFFNESS)).abs() <= 1.0);
    assert_eq!(
        r.c.set_stiffness(22, 1),
        Err(CommandError::NoSuchJoint {
            joint: 22,
            joints: 22
        })
    );
}

#[test]
fn a_stiffness_change_while_walking_moves_no_goal_more_than_a_servo_step_per_cycle() {
    let mut r = Rig::walking();
    // Joint 0 (an MX-28) near the start of the step carries about +0.3 N m
    // (0.3 cos(2 pi s / 100), s < 2). From 8.4 to 0.84 N m/rad its bias grows by
    // 0.3 x (1/0.84 - 1/8.4) = 0.321 rad = 209 ticks: five and a half MX-28 steps (37 ticks at
    // 100 Hz, 55 rev/min x 4096 / 60 / 100 = 37.5 rounded down).
    assert_eq!(r.c.joints[0].model, dynamixel::ServoModel::Mx28);
    let step = 37.0;
    let t0 = r.c.play_clock().unwrap().phase_us();
    let at = |k: u32| (t0 + 10_000 * k) as f64 / 1e6 * 100.0;
    r.c.set_stiffness(0, 840).unwrap();
    // The goal difference the change makes, from the f64 reference at the first cycle after it.
    let diff = r.gait.goal(at(1), 0, STIFFNESS) - r.gait.goal(at(1), 0, 0.84);
    assert!(
        diff < -5.0 * step,
        "the change must step more than a servo step: {diff}"
    );
    let mut before = r.servos.pos[0] as f64 - r.gait.goal(at(0), 0, STIFFNESS);
    let mut left = diff;
    for k in 1..=8 {
        r.cycle();
        // Where the goal is against the new bias's: what is left of the difference, 37 ticks
        // less each cycle after the first (which keeps the old bias's goal).
        let off = r.servos.pos[0] as f64 - r.gait.goal(at(k), 0, 0.84);
        assert!((off - left).abs() <= 2.0, "cycle {k}: {off} vs {left}");
        // Beyond what the gait itself moves (with the bias the goal had the cycle before), the
        // goal moves at most one servo step (2 ticks of rounding). Cycle 1 against the old bias:
        // the old code jumped the whole 209 ticks here.
        let now = if k == 1 {
            r.servos.pos[0] as f64 - r.gait.goal(at(1), 0, STIFFNESS)
        } else {
            off
        };
        assert!(
            (now - before).abs() <= step + 2.0,
            "cycle {k}: {before} -> {now}"
        );
        before = off;
        left = (left + step).min(0.0);
    }
    // ceil(209 / 37) = 6 cycles of steps after the first: from cycle 7 on, the new bias alone.
    assert!(before.abs() <= 1.0, "{before}");
    assert!(r.c.counters().rate_limited >= 5);
}

#[test]
fn emergency_stop_turns_torque_off_and_needs_a_clear() {
    let mut r = Rig::walking();
    r.c.emergency_stop();
    assert_eq!(r.c.state(), State::EStop);
    assert_eq!(r.cycle(), BusAction::TorqueOff);
    assert!(!r.servos.torque);
    assert_eq!(r.cycle(), BusAction::ReadOnly);
    assert!(matches!(r.try_play(None), Err(CommandError::WrongState(_))));
    r.c.clear_fault().unwrap();
    assert_eq!(r.c.state(), State::Idle);
    assert_eq!(r.servos.torque_writes, [true, false]);
}

#[test]
fn a_silent_servo_puts_the_robot_in_the_safe_state_naming_it() {
    let mut r = Rig::walking();
    r.servos.silent = vec![7];
    r.cycle();
    r.cycle();
    assert_eq!(r.c.state(), State::Walking, "two misses are tolerated");
    r.cycle();
    assert_eq!(r.c.state(), servo_missing(7));
    // No more goals: only reads.
    while r.c.pop_telemetry().is_some() {}
    assert_eq!(r.cycle(), BusAction::ReadOnly);
    assert_eq!(r.c.counters().timeouts, 4);
    // Telemetry names the silent servo.
    let last = core::iter::from_fn(|| r.c.pop_telemetry()).last().unwrap();
    assert_eq!(
        last.joints[7].flags & crate::telemetry::flags::NO_REPLY,
        crate::telemetry::flags::NO_REPLY
    );
    assert_eq!(last.joints[6].flags & crate::telemetry::flags::NO_REPLY, 0);
}

#[test]
fn after_clear_fault_a_missing_servo_gets_the_whole_miss_limit_again() {
    let mut r = Rig::walking();
    r.servos.silent = vec![7];
    r.cycles_until(10, |r| matches!(r.c.state(), State::Safe(_)));
    // Still silent while the fault stands: its misses run on.
    r.cycle();
    r.cycle();
    // The host clears the fault while a Sync Read is in flight whose reply of servo 8 is lost
    // (the servo came back a moment later than the command).
    r.cycle_with(|c, _, _| c.clear_fault().unwrap());
    assert_eq!(r.c.state(), State::Idle, "one lost reply after ClearFault");
    // The servo stays silent: the fault comes back at the third read cycle (not counting the
    // Torque Off that Idle sends first), as for a servo that was never cleared.
    let mut reads = 1;
    while r.c.state() == State::Idle {
        if matches!(r.cycle(), BusAction::ReadOnly | BusAction::Cycle) {
            reads += 1;
        }
        assert!(reads <= 3, "no fault after {reads} lost replies");
    }
    assert_eq!(reads, 3);
    assert!(
        matches!(
            r.c.state(),
            State::Safe(SafeReason::ServoMissing { joint: 7, .. })
        ),
        "{:?}",
        r.c.state()
    );
}

#[test]
fn a_hardware_error_is_named_with_its_bits_and_a_reboot_recovers() {
    let mut r = Rig::walking();
    r.servos.alert = Some(3);
    r.cycle();
    assert!(matches!(
        r.c.state(),
        State::Safe(SafeReason::ServoError {
            joint: 3,
            id: 4,
            ..
        })
    ));
    assert_eq!(r.cycle(), BusAction::ReadHardwareError { joint: 3 });
    assert_eq!(r.c.state(), servo_error(3, 0x20));
    assert!(matches!(
        r.c.reboot_servos(Some(22)),
        Err(CommandError::NoSuchJoint { joint: 22, .. })
    ));
    r.c.reboot_servos(Some(3)).unwrap();
    assert_eq!(r.cycle(), BusAction::Reboot { joints: 1 << 3 });
    assert_eq!(r.servos.reboots, 1);
    assert_eq!(r.c.state(), State::Boot);
    r.cycle();
    assert_eq!(r.c.state(), State::Idle);
}

/// The emulator soak's "never left Boot": the host's RebootServos reaches the link task while the
/// bus task awaits the replies of a Sync Read planned in Safe. Those replies predate the reboot and
/// still carry the overloaded servo's Alert; taken in Boot they faulted the board again (Safe, so
/// `Play` was refused for good) before the Reboot was even sent.
#[test]
fn replies_read_before_a_pending_reboot_do_not_fault_the_boot_waiting_for_it() {
    let mut r = Rig::walking();
    r.servos.alert = Some(3);
    r.cycle();
    assert_eq!(r.cycle(), BusAction::ReadHardwareError { joint: 3 });
    // A Sync Read goes out in Safe; the reboot command arrives before its replies are taken.
    let action = r.cycle_with(|c, _, replies| {
        assert!(matches!(replies[3], Ok(Feedback { alert: true, .. })));
        c.reboot_servos(Some(3)).unwrap();
    });
    assert_eq!(action, BusAction::ReadOnly);
    assert_eq!(r.c.state(), State::Boot, "the stale Alert faulted the Boot");
    assert_eq!(r.cycle(), BusAction::Reboot { joints: 1 << 3 });
    assert_eq!(
        r.c.state(),
        State::Boot,
        "Boot waits for the rebooted servo's answer"
    );
    assert_eq!(r.cycle(), BusAction::ReadOnly);
    assert_eq!(r.c.state(), State::Idle);
    r.play(None);
    assert_eq!(r.c.state(), State::Ramping);
}

#[test]
fn a_status_error_number_is_a_servo_error() {
    let mut r = Rig::idle_torque_off();
    let mut replies = [Ok(Feedback::default()); 22];
    replies[5] = Err(ReplyFault::Status(StatusError(0x04)));
    r.complete_with(&replies);
    assert_eq!(r.c.state(), servo_error(5, 0x04));
}

#[test]
fn every_unusable_reply_is_counted_crc_and_malformed_with_the_crc_errors() {
    let mut r = Rig::idle_torque_off();
    let mut replies = [Ok(Feedback::default()); 22];
    replies[2] = Err(ReplyFault::Crc);
    replies[7] = Err(ReplyFault::Malformed);
    replies[9] = Err(ReplyFault::Timeout);
    let before = r.c.counters();
    r.complete_with(&replies);
    let after = r.c.counters();
    // Three replies lost: two came but were unusable, one never came.
    assert_eq!(after.crc_errors - before.crc_errors, 2);
    assert_eq!(after.timeouts - before.timeouts, 1);
}

#[test]
fn replies_lost_to_an_upload_stalling_the_chip_are_no_servo_fault_but_real_misses_still_are() {
    let mut r = Rig::idle_torque_off();
    let table = r.gait.build();
    r.c.upload_begin(1, table.len() as u32).unwrap();
    // Servo 5 (joint 4) loses its reply in five cycles in a row, each with a flash write in it.
    r.servos.silent = vec![4];
    let chunk = 64;
    for (i, part) in table.chunks(chunk).take(5).enumerate() {
        r.cycle_with(|c, _, _| c.upload_chunk((i * chunk) as u32, part).unwrap());
        assert_eq!(r.c.state(), State::Idle, "cycle {i} with a flash write");
    }
    assert_eq!(
        r.c.counters().timeouts,
        5,
        "the lost replies are still counted"
    );
    // The same silence without flash work is a missing servo at the third cycle, as always.
    r.cycle();
    r.cycle();
    assert_eq!(r.c.state(), State::Idle);
    r.cycle();
    assert_eq!(r.c.state(), servo_missing(4));
}

#[test]
fn uploads_are_refused_while_walking_and_the_table_stays() {
    let mut r = Rig::idle();
    r.play(None);
    r.cycle();
    assert_eq!(r.c.state(), State::Ramping);
    assert_eq!(
        r.c.upload_begin(1, 1000),
        Err(CommandError::Moving {
            state: State::Ramping
        })
    );
    assert!(matches!(
        r.c.delete_gait(0),
        Err(CommandError::Moving { .. })
    ));
    assert!(r.c.store().table(0).is_some());
}

#[test]
fn telemetry_every_nth_cycle_and_drops_counted_when_nobody_reads() {
    let mut r = Rig::new();
    r.c.set_telemetry(3);
    for _ in 0..9 {
        r.cycle();
    }
    let cycles: Vec<u32> = core::iter::from_fn(|| r.c.pop_telemetry())
        .map(|t| t.cycle)
        .collect();
    // Telemetry comes from feedback cycles: cycle 2 is the fresh boot's Torque Off (no feedback),
    // so the feedback cycles are 1, 3, 4, 5, ... and every third of them, from the first, is
    // reported: cycles 1, 5, 8.
    assert_eq!(cycles, [1, 5, 8]);
    r.c.set_telemetry(1);
    for _ in 0..20 {
        r.cycle();
    }
    assert_eq!(r.c.telemetry_dropped(), 20 - TELEMETRY_QUEUE as u32);
}

#[test]
fn a_watchdog_reset_stays_safe_until_cleared() {
    let mut r = Rig::new();
    r.c.watchdog_reset();
    assert_eq!(r.c.state(), State::Safe(SafeReason::Watchdog));
    r.cycle();
    assert_eq!(r.c.state(), State::Safe(SafeReason::Watchdog));
    assert!(r.try_play(None).is_err());
    r.c.clear_fault().unwrap();
    assert_eq!(r.c.state(), State::Idle);
}

#[test]
fn streaming_follows_setpoints_and_faults_when_they_stop() {
    let mut r = Rig::idle();
    r.c.set_torque(true).unwrap();
    assert_eq!(r.cycle(), BusAction::TorqueOn);
    assert_eq!(r.c.state(), State::Standing);
    r.c.enter_streaming(3, 1).unwrap();
    assert_eq!(r.c.state(), State::Streaming);
    // Joint 0: +0.1 rad with no torque; zero 2048 - 100 + 0 = 1948 (testkit), sign +1:
    // 0.1 rad x 4096 / 2 pi = 65.19 -> 65 ticks.
    let mut sp = vec![(0, None); JOINTS];
    sp[0] = (100_000, None);
    r.c.setpoint(7, &sp).unwrap();
    // The servo stands at 1800 (IdealServos), 213 ticks from 2013: the goal moves one MX-28 step
    // per cycle toward it (55 rev/min x 4096 / 60 / 100 Hz = 37.5 -> 37 ticks), not at once.
    assert_eq!(r.c.joints[0].model, dynamixel::ServoModel::Mx28);
    r.cycle();
    assert_eq!(r.servos.pos[0], 1800 + 37);
    assert_eq!(r.c.stream_status(), (7, 1));
    // Wrong number of joints is refused and changes nothing.
    assert!(r.c.setpoint(8, &sp[..3]).is_err());
    r.cycle();
    r.cycle();
    assert_eq!(r.c.state(), State::Streaming);
    r.cycle();
    assert_eq!(r.c.state(), State::Safe(SafeReason::SetpointTimeout));
}

#[test]
fn run_time_stiffness_survives_playing_the_same_gait_again() {
    let mut r = Rig::idle();
    r.c.set_stiffness(2, 1234).unwrap();
    r.play(Some(1));
    assert_eq!(r.c.stiffness()[2], 1234);
    r.until(3000, State::Standing);
    r.play(Some(1));
    assert_eq!(r.c.stiffness()[2], 1234);
    // The table's own value for the joints not overridden.
    assert_eq!(r.c.stiffness()[3], 8400);
}

#[test]
fn a_jammed_servo_is_reported_at_the_end_of_the_first_whole_window_after_the_jam() {
    let mut r = Rig::idle();
    r.play(None);
    assert_eq!(r.cycle(), BusAction::TorqueOn);
    let window = usize::from(Config::default().stuck.window);
    // Every cycle from here on writes goals with torque on and every servo answers: one sample
    // each. Walk (past the ramp) to the middle of a window.
    let mut samples = 0;
    while !(r.c.state() == State::Walking
        && samples >= 4 * window
        && samples % window == window / 2)
    {
        assert_eq!(r.cycle(), BusAction::Cycle);
        samples += 1;
    }
    r.servos.stuck = vec![4];
    // The window in progress saw joint 4 move for half its length: no fault at its end. The next
    // one is all jam: the fault comes with its last sample.
    let fire_at = samples - samples % window + 2 * window;
    let (mut lo, mut hi) = (f64::MAX, f64::MIN);
    while samples < fire_at {
        assert_eq!(r.c.state(), State::Walking, "sample {samples}");
        // The goal this cycle writes, from the gait's formula (the clock advances 10 ms first).
        let t = (r.c.play_clock().unwrap().phase_us() + 10_000) % 1_000_000;
        let want = r.gait.goal(t as f64 / 1e6 * 100.0, 4, STIFFNESS);
        if samples >= fire_at - window {
            (lo, hi) = (lo.min(want), hi.max(want));
        }
        r.cycle();
        samples += 1;
    }
    let State::Safe(SafeReason::ServoStuck {
        joint: 4,
        id: 5,
        goal_range,
        present_range: 0,
    }) = r.c.state()
    else {
        panic!("{:?} at sample {samples}", r.c.state());
    };
    // Half a period of a 0.4 rad sine is at least 0.4 rad (260 ticks) of goal range.
    assert!(
        (f64::from(goal_range) - (hi - lo)).abs() <= 2.0,
        "goal range {goal_range} vs {:.1} from the gait",
        hi - lo
    );
    assert!(goal_range > 250, "{goal_range}");
    // As for a silent servo: no more goals, only reads; then clear, unjam, walk on without a fault.
    assert_eq!(r.cycle(), BusAction::ReadOnly);
    r.servos.stuck.clear();
    r.c.clear_fault().unwrap();
    r.until(5, State::Idle);
    r.play(None);
    r.until(2000, State::Walking);
    for _ in 0..4 * window {
        r.cycle();
        assert_eq!(r.c.state(), State::Walking);
    }
}

#[test]
fn an_endless_run_without_its_host_stops_at_the_end_of_the_step() {
    // 50 silent cycles (0.5 s at 100 Hz) allowed; the step is 100 cycles (1 s).
    let mut r = Rig::walking_with(host_timeout(50));
    // A host that keeps talking keeps the robot walking: 3 steps with contact every 40 cycles.
    for i in 0..300 {
        if i % 40 == 0 {
            r.c.host_contact();
        }
        r.cycle();
        assert_eq!(r.c.state(), State::Walking, "cycle {i} with a live host");
    }
    // The host falls silent: the 51st silent cycle asks for a stop, which ends the step.
    r.c.host_contact();
    let n = r.until(60, State::Stopping);
    assert_eq!(n, 51);
    assert_eq!(r.c.counters().host_lost, 1);
    r.until(200, State::Standing);
    assert_eq!(r.c.play_clock().unwrap().phase_us(), 0, "never mid-step");
}

#[test]
fn a_finite_run_finishes_its_steps_without_a_host() {
    let mut r = Rig::idle_with(host_timeout(50));
    r.play(Some(3));
    // Ramp plus 3 steps of 100 cycles, no host contact at all: all three steps are walked.
    r.until(2000, State::Standing);
    assert_eq!(r.c.play_clock().unwrap().steps_done(), 3);
    assert_eq!(r.c.counters().host_lost, 0);
}

/// The testkit's stiffness (8.4 N m/rad) as each model's Position P Gain, by hand:
/// 1 P unit = (1/128) / 885 x stall torque x 4096 / (2 pi) N m/rad = 0.014387 (MX-28, 2.5 N m) and
/// 0.034529 (MX-64, 6.0 N m); 8.4 / 0.014387 = 583.86 -> 584, 8.4 / 0.034529 = 243.28 -> 243.
/// Each joint's servo model is the testkit gait's (its servo with ID `id` is joint `id - 1`).
fn table_gain(id: u8) -> u16 {
    match SyntheticGait::new(2, 1.0).joints[usize::from(id) - 1].model {
        dynamixel::ServoModel::Mx28 => 584,
        dynamixel::ServoModel::Mx64 => 243,
    }
}

#[test]
fn torque_on_writes_each_joints_p_gain_and_a_stiffness_change_writes_them_once() {
    let mut r = Rig::idle();
    // Torque off: the servos keep their own gain.
    r.c.set_stiffness(0, 4200).unwrap();
    assert_ne!(r.cycle(), BusAction::WriteGains);
    assert!(!r.c.torque_on());
    assert_eq!(r.servos.p_gain[0], 850);
    r.c.set_torque(true).unwrap();
    assert_eq!(r.cycle(), BusAction::TorqueOn);
    // 4.2 / 0.014387 = 291.93 -> 292.
    assert_eq!(r.servos.p_gain[0], 292);
    for j in 1..JOINTS {
        assert_eq!(r.servos.p_gain[j], table_gain(j as u8 + 1), "joint {j}");
    }
    // Torque-on wrote them all: nothing more is due.
    assert_eq!(r.cycle(), BusAction::Cycle);
    // A change with torque on: one write on the next cycle, then plain cycles again.
    r.c.set_stiffness(5, 16_800).unwrap();
    assert_eq!(r.cycle(), BusAction::WriteGains);
    // 16.8 / 0.034529 = 486.56 -> 487 (joint 5 is ID 6, an MX-64).
    assert_eq!(r.servos.p_gain[5], 487);
    assert_eq!(r.servos.p_gain[0], 292);
    for _ in 0..5 {
        assert_eq!(r.cycle(), BusAction::Cycle);
    }
    // The same value again is no change: no write.
    r.c.set_stiffness(5, 16_800).unwrap();
    assert_eq!(r.cycle(), BusAction::Cycle);
}

#[test]
fn stiffness_0_leaves_the_servos_gain_as_it_is() {
    let mut r = Rig::idle();
    r.c.set_stiffness(2, 0).unwrap();
    r.c.set_torque(true).unwrap();
    assert_eq!(r.cycle(), BusAction::TorqueOn);
    assert_eq!(r.servos.p_gain[2], 850, "bias off: the servo's own gain");
    assert_eq!(r.servos.p_gain[3], 584);
    // Switching the bias off with torque on leaves the gain the servo has, never 0.
    r.c.set_stiffness(3, 0).unwrap();
    r.cycle();
    r.cycle();
    assert_eq!(r.servos.p_gain[3], 584);
    // Every joint off: nothing to write, so no write is due.
    for j in 0..JOINTS as u8 {
        r.c.set_stiffness(j, 0).unwrap();
    }
    for _ in 0..3 {
        assert_eq!(r.cycle(), BusAction::Cycle);
    }
    assert!(r.servos.p_gain[..JOINTS].iter().all(|&p| p != 0));
}

#[test]
fn a_failed_gain_write_is_retried_on_the_next_cycle() {
    let mut r = Rig::idle();
    r.c.set_torque(true).unwrap();
    assert_eq!(r.cycle(), BusAction::TorqueOn);
    r.c.set_stiffness(0, 4200).unwrap();
    r.servos.fail_gain_writes = 2;
    assert_eq!(r.cycle(), BusAction::WriteGains);
    assert_eq!(r.cycle(), BusAction::WriteGains);
    assert_eq!(r.servos.p_gain[0], 584);
    assert_eq!(r.cycle(), BusAction::WriteGains);
    assert_eq!(r.servos.p_gain[0], 292);
    assert_eq!(r.cycle(), BusAction::Cycle);
    assert_eq!(r.c.counters().bus_errors, 2);
}

#[test]
fn a_stiffness_change_during_the_gain_write_is_written_on_the_next_cycle() {
    let mut r = Rig::idle();
    r.c.set_torque(true).unwrap();
    r.cycle();
    r.c.set_stiffness(0, 4200).unwrap();
    // The command comes while the bus task performs the write planned before it.
    let action = r.cycle_with(|c, _, _| c.set_stiffness(0, 2100).unwrap());
    assert_eq!(action, BusAction::WriteGains);
    assert_eq!(r.servos.p_gain[0], 292);
    assert_eq!(r.cycle(), BusAction::WriteGains);
    // 2.1 / 0.014387 = 145.97 -> 146.
    assert_eq!(r.servos.p_gain[0], 146);
}

//! The controller: everything the board does between the seams, with no I/O of its own. The bus
//! loop asks it for the next bus action ([`Controller::plan`]), performs it on the Dynamixel bus and
//! hands back what came of it ([`Controller::complete`]); the link handler calls the command
//! methods. The board keeps it behind a blocking mutex shared by the bus and link tasks; the host's
//! virtual robot keeps it in a `RefCell`.

mod commands;
mod cycle;
mod feedback;
#[cfg(test)]
mod gain_wire_tests;
mod health;
#[cfg(test)]
mod limits_tests;
mod platform;
mod servo_read;
mod steer;
mod switch;
#[cfg(test)]
mod tests;

use dynamixel::master::{Feedback, Goal};
use embedded_storage::nor_flash::NorFlash;

use crate::bias::JointCal;
use crate::playback::{MAX_JOINTS, PlayClock, Ramp};
use crate::safety::{MissCounter, State, StuckDetector, StuckLimits};
use crate::store::{FlashWindow, GaitStore};
use crate::telemetry::{DropQueue, Record};

pub use crate::telemetry::SetpointStamp;
pub use commands::{CommandError, PlayParams, Setting};
pub use cycle::{BusAction, CyclePlan, Outcome};
pub use servo_read::ServoReadError;
pub use switch::QUEUE_LEN;

/// Telemetry records the queue holds before it drops (about 400 B each).
pub const TELEMETRY_QUEUE: usize = 8;

/// Run-time settings of the controller.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Config {
    /// Bus cycles per second (50 to 1000).
    pub cycle_hz: u16,
    /// Bus baud rate, bit/s.
    pub baud: u32,
    /// A telemetry record every this many cycles (0 = none).
    pub telemetry_every: u16,
    /// Consecutive cycles without a usable reply after which a servo counts as missing.
    pub miss_limit: u8,
    /// Speed of the start ramp for the joint with the longest way, ticks per second.
    pub ramp_ticks_per_s: u32,
    /// Shortest start ramp, microseconds.
    pub ramp_min_us: u32,
    /// Stuck-servo detection (no message sets it: the defaults are argued in [`StuckLimits`]).
    pub stuck: StuckLimits,
    /// Host-loss rule for endless runs: bus cycles without any frame from the host after which an
    /// endless run (`Steps::Continuous`) stops at the end of its step, as if `Stop` had come
    /// (0 = no rule). A host that dies (`dbot run` killed) no longer leaves the robot walking.
    /// Finite runs finish their steps and stop on their own, host or not.
    pub host_timeout_cycles: u32,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            cycle_hz: 100,
            baud: 1_000_000,
            telemetry_every: 1,
            miss_limit: 3,
            // About 35 deg/s: slow enough to be harmless from any posture.
            ramp_ticks_per_s: 400,
            ramp_min_us: 500_000,
            stuck: StuckLimits::default(),
            // Off in the library (the in-process virtual robot lives only while its host runs);
            // the image sets `protocol::limits::HOST_TIMEOUT_CYCLES`.
            host_timeout_cycles: 0,
        }
    }
}

/// Counters since boot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Counters {
    /// Bus actions performed.
    pub cycles: u32,
    /// Cycle starts missed because the previous cycle ran past its deadline.
    pub overruns: u32,
    /// Replies that did not come in time.
    pub timeouts: u32,
    /// Replies that came but were unusable: a failed CRC, or malformed (not the status asked for).
    pub crc_errors: u32,
    /// Endless runs stopped because the host fell silent (`Config::host_timeout_cycles`).
    pub host_lost: u32,
    /// Whole bus operations that failed (UART errors).
    pub bus_errors: u32,
    /// Goals clamped to a joint limit.
    pub clamped: u32,
    /// Goal moves cut short by the per-cycle step ([`crate::goal_step`]): streamed setpoints
    /// further than the servo moves in a cycle, and the torque bias following a stiffness change
    /// while walking. Counted on the board only (not in the wire's status).
    pub rate_limited: u32,
    /// Latest cycle start lateness and the largest one seen, microseconds.
    pub jitter_us: u32,
    pub max_jitter_us: u32,
}

/// The gait being played: its slot and how its bytes are laid out (checked once at selection).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Selected {
    pub slot: u8,
    pub layout: crate::gait_view::Layout,
    /// The table's own CRC-32 (its last bytes, [`crate::gait_view::stored_crc`]): a new upload to
    /// the same slot is a new table.
    pub crc: u32,
}

/// The controller over the gait store's flash `F`.
#[derive(Debug)]
pub struct Controller<F> {
    store: GaitStore<F>,
    config: Config,
    state: State,
    joints: heapless::Vec<JointCal, MAX_JOINTS>,
    stiffness: [u32; MAX_JOINTS],
    /// Walking: the stiffness the goals' torque bias last used, and what is left of the goal
    /// difference a stiffness change made (ticks per joint), shrinking by the servo's step per
    /// cycle (`cycle::follow_stiffness`).
    bias_k: [u32; MAX_JOINTS],
    bias_residual: [i32; MAX_JOINTS],
    selected: Option<Selected>,
    play: Option<PlayClock>,
    ramp: Option<Ramp>,
    /// Goals of the last cycle (what standing holds).
    goals: [i32; MAX_JOINTS],
    /// The planned angles the goals came from, without the torque bias (ticks): the stuck rule
    /// wants both to move.
    planned: [i32; MAX_JOINTS],
    clamped: [bool; MAX_JOINTS],
    /// Telemetry flags of each joint's last reply (no reply, CRC error).
    reply_flags: [u8; MAX_JOINTS],
    /// Last good feedback per joint, and whether every joint has answered since the map changed.
    present: [Feedback; MAX_JOINTS],
    known: [bool; MAX_JOINTS],
    /// Torque as last sent to the servos.
    torque_sent: bool,
    /// Changes of the stiffness settings (selected gait, `set_stiffness`), and the one whose P
    /// gains last reached the servos: they differ while a gain write is due.
    gains_wanted: u32,
    gains_written: u32,
    /// No Torque On / Off has reached the servos since boot: a reset (watchdog, the board's own
    /// brown-out) can leave them holding torque, so Idle and EStop send Torque Off once, and what
    /// the board reports and what an emergency stop does match the servos.
    torque_unknown: bool,
    misses: MissCounter<MAX_JOINTS>,
    stuck: StuckDetector<MAX_JOINTS>,
    /// Joints whose servos are to be rebooted (bit j), if a reboot is pending.
    reboot_pending: Option<u32>,
    /// Flash operations done so far, and their number when the cycle in flight was planned: a
    /// sector erase or page program stalls the whole chip (interrupts off, XIP off), so the
    /// replies of a cycle it fell into are lost for the controller's own doing, not the servos'.
    flash_ops: u32,
    flash_ops_at_plan: u32,
    hw_error_pending: Option<u8>,
    last_plan_us: Option<u64>,
    stream: cycle::Stream,
    /// Bus cycles of an endless run since the host was last heard from.
    host_quiet: u32,
    /// Gaits to play next, each checked against the one before it when queued.
    queue: heapless::Deque<switch::Queued, { switch::QUEUE_LEN }>,
    /// Steps the gaits before the one playing completed in this run (the step count of status and
    /// telemetry runs on across switches).
    steps_before: u32,
    /// The gaits `Steer` blends (set by `set_steer_family`), and the steered walk playing.
    steer_family: Option<protocol::SteerFamily>,
    steer: Option<steer::Steering>,
    /// The perturbation platform set up, if any.
    platform: Option<platform::PlatformRun>,
    counters: Counters,
    telemetry: DropQueue<Record, TELEMETRY_QUEUE>,
    telemetry_countdown: u16,
    /// The servos' heat and supply ([`crate::safety::health`]), and the alarm that stopped the
    /// last walk (until the next `Play`).
    health: crate::safety::health::HealthWatch<MAX_JOINTS>,
    health_stop: Option<protocol::HealthAlarm>,
    /// The host's servo read waiting for a cycle with the time for it, and the last finished one
    /// ([`servo_read`]).
    servo_read: Option<protocol::ServoRead>,
    servo_read_result: Option<protocol::ServoReadResult>,
}

impl<F: NorFlash + FlashWindow> Controller<F> {
    /// Mounts the gait store on `flash` and starts in `Boot`. The joint map is the one of the gait in
    /// the lowest filled slot (none: no servos until a gait is played).
    pub fn new(flash: F, slots: u8, config: Config) -> Self {
        let store = GaitStore::mount(flash, slots);
        let mut c = Self {
            store,
            config,
            state: State::Boot,
            joints: heapless::Vec::new(),
            stiffness: [0; MAX_JOINTS],
            bias_k: [0; MAX_JOINTS],
            bias_residual: [0; MAX_JOINTS],
            selected: None,
            play: None,
            ramp: None,
            goals: [0; MAX_JOINTS],
            planned: [0; MAX_JOINTS],
            clamped: [false; MAX_JOINTS],
            reply_flags: [0; MAX_JOINTS],
            present: [Feedback::default(); MAX_JOINTS],
            known: [false; MAX_JOINTS],
            torque_sent: false,
            gains_wanted: 1,
            gains_written: 0,
            torque_unknown: true,
            misses: MissCounter::new(config.miss_limit),
            stuck: StuckDetector::new(config.stuck),
            reboot_pending: None,
            flash_ops: 0,
            flash_ops_at_plan: 0,
            hw_error_pending: None,
            last_plan_us: None,
            stream: cycle::Stream::default(),
            host_quiet: 0,
            queue: heapless::Deque::new(),
            steps_before: 0,
            steer_family: None,
            steer: None,
            platform: None,
            counters: Counters::default(),
            telemetry: DropQueue::new(),
            telemetry_countdown: 0,
            health: crate::safety::health::HealthWatch::new(protocol::HealthLimits::DEFAULT),
            health_stop: None,
            servo_read: None,
            servo_read_result: None,
        };
        if let Some(slot) = (0..c.store.slots()).find(|&s| c.store.table(s).is_some()) {
            // A table that fails validation just leaves the map empty; the host sees it in `list`.
            let _ = c.select(slot);
        }
        c
    }

    pub fn state(&self) -> State {
        self.state
    }

    pub fn config(&self) -> Config {
        self.config
    }

    pub fn counters(&self) -> Counters {
        self.counters
    }

    pub fn store(&self) -> &GaitStore<F> {
        &self.store
    }

    /// The joint map in use.
    pub fn joints(&self) -> &[JointCal] {
        &self.joints
    }

    /// Stiffness per joint, mN m/rad: the torque bias's divisor and the servos' Position P Gain.
    pub fn stiffness(&self) -> &[u32] {
        &self.stiffness[..self.joints.len()]
    }

    /// Goals of the last cycle, ticks.
    pub fn goals(&self) -> &[i32] {
        &self.goals[..self.joints.len()]
    }

    /// Last good feedback per joint.
    pub fn feedback(&self) -> &[Feedback] {
        &self.present[..self.joints.len()]
    }

    /// Whether torque is on as far as the controller knows.
    pub fn torque_on(&self) -> bool {
        self.torque_sent
    }

    /// The slot being played or last selected.
    pub fn selected_slot(&self) -> Option<u8> {
        self.selected.map(|s| s.slot)
    }

    /// Playback position: steps done and the slice the goals came from.
    pub fn playback(&self) -> Option<(u32, u16)> {
        let s = self.selected?;
        let p = self.play.as_ref()?;
        let step = self.steps_before.saturating_add(p.steps_done());
        Some((step, p.sample(s.layout.slices).slice as u16))
    }

    pub fn play_clock(&self) -> Option<&PlayClock> {
        self.play.as_ref()
    }

    /// Bus cycle period from the configured rate.
    pub fn period_us(&self) -> u32 {
        1_000_000 / u32::from(self.config.cycle_hz.max(1))
    }

    /// Next telemetry record for the host, if any.
    pub fn pop_telemetry(&mut self) -> Option<Record> {
        self.telemetry.pop()
    }

    /// Telemetry records dropped because the host did not take them in time.
    pub fn telemetry_dropped(&self) -> u32 {
        self.telemetry.dropped()
    }

    /// Gives the flash back (tests cut the power with it).
    pub fn into_flash(self) -> F {
        self.store.into_flash()
    }

    fn all_known(&self) -> bool {
        self.known[..self.joints.len()].iter().all(|&k| k)
    }

    fn goal_list(&self) -> ([Goal; MAX_JOINTS], usize) {
        let mut g = [Goal { id: 0, position: 0 }; MAX_JOINTS];
        for (i, j) in self.joints.iter().enumerate() {
            g[i] = Goal {
                id: j.id,
                position: self.goals[i],
            };
        }
        (g, self.joints.len())
    }
}

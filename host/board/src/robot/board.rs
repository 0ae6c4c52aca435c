//! [`VirtualRobot`]: the firmware library's own [`firmware::board::Board`] (controller, bus loop,
//! link dispatcher, unchanged) over the NOR flash double, its bus master talking to a FIXED virtual
//! servo chain on a simulated half-duplex wire. Time is the wire's simulated clock; the host feeds
//! frames and lets time pass, and the robot runs as fast as the CPU allows.
//!
//! The chain is the robot's: 22 servos, IDs 1..=22, MX-64 on the CTr joints (or a chain given to
//! [`VirtualRobot::with_parts`]). A table naming servos the chain lacks fails here as it would on the
//! robot. What else acts on the servos each cycle is a [`ServoDynamics`]: by default
//! [`PlannedLoads`], the planned joint torque of the slice being played as each servo's load.

use std::collections::VecDeque;

use dynamixel::master::{AutoDirection, MasterConfig};
use dynamixel::sim::{SimWire, VirtualChain, WireConfig};
use firmware::board::Board;
use firmware::controller::{Config, Controller};

use super::flash::{FLASH_SECTORS, SLOTS, VirtualFlash};
use super::servos::{PlannedLoads, ServoDynamics};

/// Servos of Drosophibot II (IDs 1..=22).
pub const ROBOT_SERVOS: u8 = 22;
/// Reply slack of the bus master, as the board's firmware sets it for servos with Return Delay
/// Time 0 (firmware/src/rp.rs).
const REPLY_SLACK_US: u32 = 300;

/// The firmware's board over the simulated wire.
pub type VirtualBoard = Board<VirtualFlash, SimWire, AutoDirection, SimWire>;

/// A simulated board with its servos, moved by `S` between bus cycles.
#[derive(Debug)]
pub struct VirtualRobot<S: ServoDynamics = PlannedLoads> {
    board: VirtualBoard,
    wire: SimWire,
    servos: S,
    to_host: VecDeque<u8>,
}

impl Default for VirtualRobot {
    fn default() -> Self {
        Self::new()
    }
}

/// The servos of Drosophibot II, `(id, model)`, as its model file (`drosophibot2.toml`) maps them.
pub fn robot_servos() -> Vec<(u8, dynamixel::ServoModel)> {
    planner::model::builtin("drosophibot2")
        .expect("the built-in model parses (tested in the planner)")
        .servo_chain()
}

/// The robot's servo chain at `baud` (which joint carries which servo read from the model file),
/// set up with Return Delay Time 0 as the firmware's reply slack assumes (at the factory 500 us
/// per servo, a 22-servo cycle would not fit 100 Hz).
pub fn robot_chain(baud: u32) -> VirtualChain {
    let mut chain =
        VirtualChain::new(&robot_servos(), baud).expect("the board's baud is a servo baud");
    chain.set_return_delay_all(0);
    chain
}

impl VirtualRobot {
    /// A board with an erased gait store and the 22 servos of Drosophibot II (default IDs).
    pub fn new() -> Self {
        Self::with_flash(VirtualFlash::new(FLASH_SECTORS))
    }

    /// A board that boots from `flash` (e.g. the flash of a robot that was switched off).
    pub fn with_flash(flash: VirtualFlash) -> Self {
        let config = Config::default();
        Self::with_parts(flash, robot_chain(config.baud), PlannedLoads)
    }
}

impl<S: ServoDynamics> VirtualRobot<S> {
    /// A board on `flash` whose bus carries `chain` (fixed for the robot's life), moved by
    /// `servos` each cycle.
    pub fn with_parts(flash: VirtualFlash, chain: VirtualChain, servos: S) -> Self {
        let config = Config::default();
        let wire = SimWire::new(
            chain,
            WireConfig {
                baud: config.baud,
                echo: true,
            },
        );
        let board = Board::new(
            flash,
            SLOTS,
            config,
            wire.clone(),
            AutoDirection,
            wire.clone(),
            REPLY_SLACK_US,
        );
        Self {
            board,
            wire,
            servos,
            to_host: VecDeque::new(),
        }
    }

    /// Switches the board off and gives its flash back.
    pub fn into_flash(self) -> VirtualFlash {
        self.board.controller.into_inner().into_flash()
    }

    /// The controller (state, counters, goals, feedback).
    pub fn controller(&self) -> std::cell::Ref<'_, Controller<VirtualFlash>> {
        self.board.controller.borrow()
    }

    /// The servo chain (read its servos, set faults or loads).
    pub fn with_chain<R>(&self, f: impl FnOnce(&mut VirtualChain) -> R) -> R {
        self.wire.with_chain(f)
    }

    /// The simulated bus wire itself, for a second master on it (the bring-up check reads the
    /// servos' registers through it, as a U2D2 clipped onto the robot's bus would).
    pub fn wire(&self) -> SimWire {
        self.wire.clone()
    }

    /// What moves the servos.
    pub fn servos(&self) -> &S {
        &self.servos
    }

    /// What moves the servos, to change.
    pub fn servos_mut(&mut self) -> &mut S {
        &mut self.servos
    }

    /// Timing of the bus loop since power-on (cycles, overruns, lateness, busy time).
    pub fn timing(&self) -> firmware::bus_loop::Timing {
        self.board.timing()
    }

    /// Bytes master -> servos and servos -> master so far.
    pub fn bus_bytes(&self) -> (u64, u64) {
        self.wire.byte_counts()
    }

    /// Simulated time since power-on, us.
    pub fn now_us(&self) -> u64 {
        self.wire.now_us()
    }

    /// Bytes from the host: every complete frame is handled at once and its reply queued.
    pub fn receive(&mut self, bytes: &[u8]) {
        let out = &mut self.to_host;
        self.board.receive(bytes, |frame| out.extend(frame));
    }

    /// Bytes waiting for the host.
    pub fn pending(&self) -> usize {
        self.to_host.len()
    }

    /// Moves up to `buf.len()` bytes for the host into `buf`.
    pub fn take(&mut self, buf: &mut [u8]) -> usize {
        let n = buf.len().min(self.to_host.len());
        for (b, x) in buf.iter_mut().zip(self.to_host.drain(..n)) {
            *b = x;
        }
        n
    }

    /// Start of the next bus cycle, us: the bus loop's next grid point (after an overrun the one
    /// it skips to), or now if that point has passed or no cycle has run yet.
    pub fn next_cycle_us(&self) -> u64 {
        let now = self.now_us();
        self.board
            .schedule
            .next_start_us()
            .map_or(now, |t| t.max(now))
    }

    /// Lets time pass up to `t_us`, running every bus cycle that starts before it.
    pub fn run_until(&mut self, t_us: u64) {
        while self.next_cycle_us() <= t_us {
            self.cycle();
        }
        let now = self.now_us();
        if t_us > now {
            self.wire.advance_us(t_us - now);
        }
    }

    /// Runs the next bus cycle of the firmware's bus loop (time passes to its start and through
    /// its bus traffic) and queues its telemetry for the host.
    ///
    /// What moves the servos is stepped to the cycle's START, not to the wire's clock: the wire's
    /// clock stands wherever the last bus traffic ended, so stepping to it would let the bytes on
    /// the bus (a register read more or less) move the simulated body.
    pub fn cycle(&mut self) {
        self.follow_baud();
        {
            let start = self.next_cycle_us();
            let c = self.board.controller.borrow();
            let servos = &mut self.servos;
            self.wire
                .with_chain(|chain| servos.before_cycle(&c, chain, start));
        }
        self.wire.clone().block_on(self.board.run_cycle());
        let out = &mut self.to_host;
        self.board.drain_telemetry(|frame| out.extend(frame));
    }

    /// `SetBus` changed the board's baud: the wire and the bus master follow, as the board's UART
    /// does. The virtual servos keep their own Baud Rate register, as real ones keep theirs in
    /// EEPROM: a board switched alone no longer hears them (`rules::bus` checks and undoes that).
    fn follow_baud(&mut self) {
        let want = self.board.controller.borrow().config().baud;
        if want == self.board.bus.config().baud {
            return;
        }
        if dynamixel::control_table::baud_code(want).is_none() {
            return;
        }
        self.wire.set_baud(want);
        self.board.bus.set_config(MasterConfig {
            baud: want,
            reply_slack_us: REPLY_SLACK_US,
        });
    }
}

//! [`VirtualRobot`]: the firmware library's controller, bus loop and link dispatcher, unchanged,
//! over the NOR flash double, with the dynamixel crate's bus master talking to its virtual servo
//! chain on a simulated half-duplex wire. Time is the wire's simulated clock; the host feeds frames
//! and lets time pass, and the robot runs as fast as the CPU allows.
//!
//! The servos carry the planned joint torque of the slice being played as their external load, so
//! load registers, the torque bias and the tracking error behave as on a robot whose legs meet the
//! loads the plan predicts.

use std::cell::RefCell;
use std::collections::VecDeque;

use dynamixel::master::{AutoDirection, BusMaster, MasterConfig};
use dynamixel::sim::{SimWire, VirtualChain, VirtualServo, WireConfig};
use firmware::bus_loop::BusLoop;
use firmware::controller::{Config, Controller};
use firmware::link::Link;
use firmware::store::nor_double::NorDouble;
use protocol::{GaitTable, ServoModel};

/// The flash double of the virtual board (4-byte write unit, like the firmware tests).
pub type VirtualFlash = NorDouble<4>;

/// Gait slots of the virtual board, as on the real one.
pub const SLOTS: u8 = firmware::store::BOARD_SLOTS;
/// Sectors of the virtual gait store: the board's gait store region.
pub const FLASH_SECTORS: usize =
    firmware::memory_map::GAIT_STORE_SIZE as usize / firmware::store::nor_double::SECTOR;
/// Reply slack of the bus master, as the board's firmware sets it for servos with Return Delay
/// Time 0 (firmware/src/rp.rs).
const REPLY_SLACK_US: u32 = 300;

type Master = BusMaster<SimWire, AutoDirection, SimWire>;

/// A simulated board with its servos.
#[derive(Debug)]
pub struct VirtualRobot {
    controller: RefCell<Controller<VirtualFlash>>,
    link: Link,
    wire: SimWire,
    master: Master,
    schedule: BusLoop,
    to_host: VecDeque<u8>,
}

impl Default for VirtualRobot {
    fn default() -> Self {
        Self::new()
    }
}

impl VirtualRobot {
    /// A board with an erased gait store and the 22 servos of Drosophibot II (default IDs).
    pub fn new() -> Self {
        Self::with_flash(VirtualFlash::new(FLASH_SECTORS))
    }

    /// A board that boots from `flash` (e.g. the flash of a robot that was switched off).
    pub fn with_flash(flash: VirtualFlash) -> Self {
        let config = Config::default();
        let mut chain =
            VirtualChain::drosophibot(22, config.baud).expect("1 Mbit/s is a servo baud rate");
        // The robot's servos are set up with Return Delay Time 0, as the firmware's reply slack
        // assumes (at the factory 500 us per servo, a 22-servo cycle would not fit 100 Hz).
        chain.set_return_delay_all(0);
        let wire = SimWire::new(
            chain,
            WireConfig {
                baud: config.baud,
                echo: true,
            },
        );
        let master = BusMaster::new(
            wire.clone(),
            AutoDirection,
            wire.clone(),
            MasterConfig {
                baud: config.baud,
                reply_slack_us: REPLY_SLACK_US,
            },
        );
        let robot = Self {
            controller: RefCell::new(Controller::new(flash, SLOTS, config)),
            link: Link::new(),
            wire,
            master,
            schedule: BusLoop::new(),
            to_host: VecDeque::new(),
        };
        robot.match_servos_to_joint_map();
        robot
    }

    /// Switches the board off and gives its flash back.
    pub fn into_flash(self) -> VirtualFlash {
        self.controller.into_inner().into_flash()
    }

    /// The controller (state, counters, goals, feedback).
    pub fn controller(&self) -> std::cell::Ref<'_, Controller<VirtualFlash>> {
        self.controller.borrow()
    }

    /// The servo chain (read its servos, set faults or loads).
    pub fn with_chain<R>(&self, f: impl FnOnce(&mut VirtualChain) -> R) -> R {
        self.wire.with_chain(f)
    }

    /// Timing of the bus loop since power-on (cycles, overruns, lateness, busy time).
    pub fn timing(&self) -> firmware::bus_loop::Timing {
        self.schedule.timing
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
        self.link
            .receive(&self.controller, bytes, &mut |frame| out.extend(frame));
        self.match_servos_to_joint_map();
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

    /// Start of the next bus cycle, us (later if the bus loop has to skip an overrun start).
    pub fn next_cycle_us(&self) -> u64 {
        let t = self.schedule.timing;
        if t.cycles == 0 {
            return self.now_us();
        }
        t.last_start_us + u64::from(self.controller.borrow().period_us())
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
    pub fn cycle(&mut self) {
        self.follow_baud();
        self.apply_loads();
        self.wire
            .block_on(self.schedule.run_cycle(&self.controller, &mut self.master));
        while let Some(frame) = self.link.telemetry(&self.controller) {
            self.to_host.extend(frame);
        }
    }

    /// `SetBus` changed the board's baud: the wire and the bus master follow, as the board's UART
    /// does, and the virtual servos are taken to be set up for it (on a robot: `dbot dxl setup`
    /// first), as they are fitted to the joint map.
    fn follow_baud(&mut self) {
        let want = self.controller.borrow().config().baud;
        if want == self.master.config().baud {
            return;
        }
        let Some(code) = dynamixel::control_table::baud_code(want) else {
            return;
        };
        self.wire.set_baud(want);
        self.master.set_config(MasterConfig {
            baud: want,
            reply_slack_us: REPLY_SLACK_US,
        });
        self.wire.with_chain(|chain| {
            for s in chain.servos_mut() {
                s.put(dynamixel::control_table::BAUD_RATE, u32::from(code));
            }
        });
    }

    /// The robot's servos are the ones its gait's joint map names: when the map names IDs or models
    /// the chain lacks, those servos are fitted (lying a few degrees off their zero, so the start
    /// ramp has work to do). A real robot is built to match its model; this keeps the virtual one so.
    fn match_servos_to_joint_map(&self) {
        let c = self.controller.borrow();
        let Some(table) = c
            .selected_slot()
            .and_then(|s| c.store().table(s))
            .and_then(|b| GaitTable::parse(b).ok())
        else {
            return;
        };
        let baud = c.config().baud;
        let Some(code) = dynamixel::control_table::baud_code(baud) else {
            return;
        };
        let wanted: Vec<(u8, ServoModel, i32)> = (0..table.joint_count())
            .filter_map(|j| table.joint(j).map(|m| (j, m)))
            .map(|(j, m)| {
                let rest = i32::from(m.zero_offset) + (j as i32 * 37) % 61 - 30;
                (m.servo_id, m.model, rest)
            })
            .collect();
        self.wire.with_chain(|chain| {
            let fits = wanted
                .iter()
                .all(|&(id, model, _)| chain.servo(id).is_some_and(|s| s.model() == model));
            if fits {
                return;
            }
            let list: Vec<(u8, ServoModel)> = wanted.iter().map(|&(id, m, _)| (id, m)).collect();
            let Ok(mut fresh) = VirtualChain::new(&list, baud) else {
                return;
            };
            for (slot, &(id, model, rest)) in fresh.servos_mut().iter_mut().zip(&wanted) {
                *slot = match chain.servo(id) {
                    Some(old) if old.model() == model => old.clone(),
                    _ => {
                        let mut s = VirtualServo::new(id, model, code, rest);
                        s.put(dynamixel::control_table::RETURN_DELAY_TIME, 0);
                        s
                    }
                };
            }
            *chain = fresh;
        });
    }

    /// The planned torque of the slice being played is the load each servo carries: the servo
    /// must deliver `sign * torque`, so the load pushes the other way.
    fn apply_loads(&mut self) {
        let c = self.controller.borrow();
        let (Some(slot), Some((_, slice))) = (c.selected_slot(), c.playback()) else {
            return;
        };
        let Some(table) = c.store().table(slot).and_then(|b| GaitTable::parse(b).ok()) else {
            return;
        };
        self.wire.with_chain(|chain| {
            for j in 0..table.joint_count() {
                let (Some(map), Some(torque)) =
                    (table.joint(j), table.torque(usize::from(slice), j))
                else {
                    continue;
                };
                let nm = protocol::units::torque_to_nm(torque) * f64::from(map.sign.as_i32());
                let _ = chain.set_external_torque(map.servo_id, -nm);
            }
        });
    }
}

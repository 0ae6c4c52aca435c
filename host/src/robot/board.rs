//! [`VirtualRobot`]: the firmware library's controller and link dispatcher, unchanged, over the
//! NOR flash double, with [`SimServos`] on the bus and a simulated clock. The host feeds it frames
//! and lets simulated time pass; it runs as fast as the CPU allows.

use std::cell::RefCell;
use std::collections::VecDeque;

use dynamixel::control_table::Model;
use dynamixel::master::{Reply, ReplyFault};
use firmware::controller::{Config, Controller};
use firmware::link::Link;
use firmware::store::nor_double::NorDouble;
use protocol::{GaitTable, ServoModel};

use super::servos::SimServos;

/// The flash double of the virtual board (4-byte write unit, like the firmware tests).
pub type VirtualFlash = NorDouble<4>;

/// Gait slots of the virtual board, as on the real one.
pub const SLOTS: u8 = firmware::store::BOARD_SLOTS;
/// Sectors of the virtual gait store: the board's gait store region.
pub const FLASH_SECTORS: usize =
    firmware::memory_map::GAIT_STORE_SIZE as usize / firmware::store::nor_double::SECTOR;

/// A simulated board with its servos.
#[derive(Debug)]
pub struct VirtualRobot {
    controller: RefCell<Controller<VirtualFlash>>,
    link: Link,
    servos: SimServos,
    now_us: u64,
    next_cycle_us: u64,
    last_cycle_us: Option<u64>,
    to_host: VecDeque<u8>,
}

impl Default for VirtualRobot {
    fn default() -> Self {
        Self::new()
    }
}

impl VirtualRobot {
    /// A board with an erased gait store.
    pub fn new() -> Self {
        Self::with_flash(VirtualFlash::new(FLASH_SECTORS))
    }

    /// A board that boots from `flash` (e.g. the flash of a robot that was switched off).
    pub fn with_flash(flash: VirtualFlash) -> Self {
        Self {
            controller: RefCell::new(Controller::new(flash, SLOTS, Config::default())),
            link: Link::new(),
            servos: SimServos::new(),
            now_us: 0,
            next_cycle_us: 0,
            last_cycle_us: None,
            to_host: VecDeque::new(),
        }
    }

    /// Switches the board off and gives its flash back.
    pub fn into_flash(self) -> VirtualFlash {
        self.controller.into_inner().into_flash()
    }

    /// The controller (state, counters, goals, feedback).
    pub fn controller(&self) -> std::cell::Ref<'_, Controller<VirtualFlash>> {
        self.controller.borrow()
    }

    pub fn servos(&self) -> &SimServos {
        &self.servos
    }

    /// Simulated time since power-on, us.
    pub fn now_us(&self) -> u64 {
        self.now_us
    }

    /// Bytes from the host: every complete frame is handled at once and its reply queued.
    pub fn receive(&mut self, bytes: &[u8]) {
        let out = &mut self.to_host;
        self.link
            .receive(&self.controller, bytes, &mut |frame| out.extend(frame));
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

    /// Start of the next bus cycle, us.
    pub fn next_cycle_us(&self) -> u64 {
        self.next_cycle_us
    }

    /// Lets time pass up to `t_us`, running every bus cycle that starts before it.
    pub fn run_until(&mut self, t_us: u64) {
        while self.next_cycle_us <= t_us {
            self.cycle();
        }
        self.now_us = self.now_us.max(t_us);
    }

    /// Runs the next bus cycle (time jumps to its start) and queues its telemetry.
    pub fn cycle(&mut self) {
        let start = self.next_cycle_us;
        self.now_us = self.now_us.max(start);
        let plan = self.controller.borrow_mut().plan(start);
        self.add_missing_servos(plan.goals().iter().map(|g| g.id));
        self.apply_loads();
        let dt_s = self
            .last_cycle_us
            .map_or(0.0, |t| (start - t) as f64 * 1e-6);
        self.last_cycle_us = Some(start);
        let (baud, period) = {
            let c = self.controller.borrow();
            (c.config().baud, u64::from(c.period_us()))
        };
        let mut replies: [Reply; protocol::MAX_JOINTS] =
            [Err(ReplyFault::Timeout); protocol::MAX_JOINTS];
        let outcome = self.servos.perform(&plan, dt_s, baud, &mut replies);
        self.controller
            .borrow_mut()
            .complete(&plan, outcome, &replies[..plan.n], 0);
        while let Some(frame) = self.link.telemetry(&self.controller) {
            self.to_host.extend(frame);
        }
        self.next_cycle_us = start + period.max(1);
    }

    /// Servos the robot has appear on the bus the first time the controller addresses them, lying
    /// near their zero (a robot resting on its belly) with the model its joint map names.
    fn add_missing_servos(&mut self, ids: impl Iterator<Item = u8>) {
        let c = self.controller.borrow();
        let table = c
            .selected_slot()
            .and_then(|s| c.store().table(s))
            .and_then(|b| GaitTable::parse(b).ok());
        for (j, id) in ids.enumerate() {
            if self.servos.get(id).is_some() {
                continue;
            }
            let (model, zero) = match table.as_ref().and_then(|t| t.joint(j)) {
                Some(m) => (dxl_model(m.model), f64::from(m.zero_offset)),
                None => (Model::Mx28V2, 2048.0),
            };
            // A few degrees off the zero, different per joint, so the start ramp has work to do.
            let rest = zero + f64::from((j as i32 * 37) % 61 - 30);
            self.servos.add(id, model, rest);
        }
    }

    /// The planned torque of the slice being played is the load each servo carries.
    fn apply_loads(&mut self) {
        let c = self.controller.borrow();
        let (Some(slot), Some((_, slice))) = (c.selected_slot(), c.playback()) else {
            return;
        };
        let Some(table) = c.store().table(slot).and_then(|b| GaitTable::parse(b).ok()) else {
            return;
        };
        for j in 0..table.joint_count() {
            let (Some(map), Some(torque)) = (table.joint(j), table.torque(usize::from(slice), j))
            else {
                continue;
            };
            let nm = protocol::units::torque_to_nm(torque) * f64::from(map.sign.as_i32());
            self.servos.set_load(map.servo_id, nm);
        }
    }
}

fn dxl_model(m: ServoModel) -> Model {
    match m {
        ServoModel::Mx64 => Model::Mx64V2,
        _ => Model::Mx28V2,
    }
}

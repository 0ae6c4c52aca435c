//! The fixed-rate bus loop: cycle starts on a grid of `1 / cycle_hz`, each cycle asks the controller
//! what to do, does it on the Dynamixel bus and hands back the result. A cycle that runs past the
//! next start makes the loop skip to the following grid point and count every missed start as an
//! overrun; how late each start really was (jitter) is measured on the bus master's clock.

use core::cell::RefCell;

use dynamixel::control_table::{GOAL_POSITION, HARDWARE_ERROR_STATUS, TORQUE_ENABLE};
use dynamixel::master::{BusError, BusMaster, Clock, DirectionPin, Reply, ReplyFault};
use embedded_io_async::{Read, Write};
use embedded_storage::nor_flash::NorFlash;

use crate::controller::{BusAction, Controller, CyclePlan, Outcome};
use crate::playback::MAX_JOINTS;
use crate::store::FlashWindow;

/// Access to the controller shared by the bus and link tasks: the board uses a blocking mutex,
/// the host a `RefCell`. Closures must be short: never `.await` inside.
pub trait Shared<T> {
    fn with<R>(&self, f: impl FnOnce(&mut T) -> R) -> R;
}

impl<T> Shared<T> for RefCell<T> {
    fn with<R>(&self, f: impl FnOnce(&mut T) -> R) -> R {
        f(&mut self.borrow_mut())
    }
}

/// Timing of the loop since it started.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Timing {
    pub cycles: u64,
    /// Cycle starts skipped because a cycle ran past them.
    pub overruns: u64,
    /// Lateness of cycle starts against the grid, microseconds.
    pub max_late_us: u32,
    pub sum_late_us: u64,
    /// Longest bus action, microseconds.
    pub max_busy_us: u32,
    pub first_start_us: u64,
    pub last_start_us: u64,
}

impl Timing {
    /// Cycles per second over the run, from the first to the last start.
    pub fn rate_hz(&self) -> f64 {
        let span = self.last_start_us.saturating_sub(self.first_start_us);
        if self.cycles < 2 || span == 0 {
            return 0.0;
        }
        (self.cycles - 1) as f64 * 1e6 / span as f64
    }
}

/// The loop's schedule.
#[derive(Debug, Clone, Default)]
pub struct BusLoop {
    next_us: Option<u64>,
    pub timing: Timing,
}

impl BusLoop {
    pub fn new() -> Self {
        Self::default()
    }

    /// Runs one cycle: waits for its start on the grid, plans, performs and completes it.
    pub async fn run_cycle<S, F, IO, D, C>(&mut self, shared: &S, bus: &mut BusMaster<IO, D, C>)
    where
        S: Shared<Controller<F>>,
        F: NorFlash + FlashWindow,
        IO: Read + Write,
        D: DirectionPin,
        C: Clock,
    {
        let (period, baud) = shared.with(|c| (u64::from(c.period_us()), c.config().baud));
        if bus.config().baud != baud {
            let mut cfg = *bus.config();
            cfg.baud = baud;
            bus.set_config(cfg);
        }
        let due = *self.next_us.get_or_insert_with(|| bus.clock().now_us());
        bus.clock().wait_until(due).await;
        let start = bus.clock().now_us();
        let late = start.saturating_sub(due).min(u32::MAX as u64) as u32;
        let plan = shared.with(|c| c.plan(start));
        let mut replies = [Err(ReplyFault::Timeout); MAX_JOINTS];
        let outcome = perform(&plan, bus, &mut replies).await;
        let end = bus.clock().now_us();

        let mut next = due + period;
        let mut missed = 0u32;
        if end > next {
            let behind = (end - next).div_ceil(period);
            missed = behind.min(u32::MAX as u64) as u32;
            next += behind * period;
        }
        self.next_us = Some(next);
        shared.with(|c| {
            c.complete(&plan, outcome, &replies[..plan.n], late);
            c.count_overruns(missed);
        });

        let t = &mut self.timing;
        if t.cycles == 0 {
            t.first_start_us = start;
        }
        t.cycles += 1;
        t.last_start_us = start;
        t.overruns += u64::from(missed);
        t.max_late_us = t.max_late_us.max(late);
        t.sum_late_us += u64::from(late);
        t.max_busy_us = t
            .max_busy_us
            .max(end.saturating_sub(start).min(u32::MAX as u64) as u32);
    }
}

/// Performs `plan.action` on the bus.
pub async fn perform<IO, D, C>(
    plan: &CyclePlan,
    bus: &mut BusMaster<IO, D, C>,
    replies: &mut [Reply],
) -> Outcome
where
    IO: Read + Write,
    D: DirectionPin,
    C: Clock,
{
    let (ids, n) = plan.ids();
    let ids = &ids[..n];
    match plan.action {
        BusAction::Nothing => Outcome::Done(Ok(())),
        BusAction::Cycle => Outcome::Feedback(bus.cycle(plan.goals(), replies).await),
        BusAction::ReadOnly => Outcome::Feedback(bus.read_feedback(ids, replies).await),
        BusAction::TorqueOn => {
            let mut bytes = [[0u8; 4]; MAX_JOINTS];
            for (b, g) in bytes.iter_mut().zip(plan.goals()) {
                *b = g.position.to_le_bytes();
            }
            let goals = plan.goals().iter().zip(&bytes).map(|(g, b)| (g.id, &b[..]));
            let r = match bus.sync_write(GOAL_POSITION.addr, 4, goals).await {
                Ok(()) => torque(bus, ids, 1).await,
                Err(e) => Err(e),
            };
            Outcome::Done(r)
        }
        BusAction::TorqueOff => Outcome::Done(torque(bus, ids, 0).await),
        BusAction::Reboot => {
            let mut result = Ok(());
            for &id in ids {
                if let Err(e) = bus.reboot(id).await {
                    result = Err(e);
                }
            }
            Outcome::Done(result)
        }
        BusAction::ReadHardwareError { joint } => {
            let Some(&id) = ids.get(usize::from(joint)) else {
                return Outcome::HardwareError(Ok(0));
            };
            let mut bits = [0u8; 1];
            let r = bus.read(id, HARDWARE_ERROR_STATUS.addr, &mut bits).await;
            Outcome::HardwareError(r.map(|_| bits[0]))
        }
    }
}

async fn torque<IO, D, C>(bus: &mut BusMaster<IO, D, C>, ids: &[u8], on: u8) -> Result<(), BusError>
where
    IO: Read + Write,
    D: DirectionPin,
    C: Clock,
{
    let value = [on];
    bus.sync_write(
        TORQUE_ENABLE.addr,
        1,
        ids.iter().map(|&id| (id, &value[..])),
    )
    .await
}

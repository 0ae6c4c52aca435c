//! The fixed-rate bus loop: cycle starts on a grid of `1 / cycle_hz`, each cycle asks the controller
//! what to do, does it on the Dynamixel bus and hands back the result. A cycle that runs past the
//! next start makes the loop skip to the following grid point and count every missed start as an
//! overrun; how late each start really was (jitter) is measured on the bus master's clock.
//!
//! Heat and supply cost the cycle rate nothing: after the cycle's own bus action, the loop reads
//! one servo's Present Input Voltage and Present Temperature (144..=146, one 3-byte Read) in the
//! time left before the next start, and only if the read's longest duration
//! ([`health_read_budget_us`]) fits there; each servo in turn, so at 100 Hz every servo of the
//! 22 is read every 0.22 s, far faster than a servo heats.

use core::cell::RefCell;

use dynamixel::control_table::{
    GOAL_POSITION, HARDWARE_ERROR_STATUS, POSITION_P_GAIN, PRESENT_INPUT_VOLTAGE, PRESENT_POSITION,
    PROFILE_VELOCITY, TORQUE_ENABLE,
};
use dynamixel::master::{
    BusError, BusMaster, Clock, DirectionPin, MasterConfig, Reply, ReplyFault,
};
use embedded_io_async::{Read, ReadReady, Write};
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
    /// Heat and supply reads done in the cycles' slack.
    pub health_reads: u64,
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

    /// When the next cycle starts on the grid, us (`None` before the first, which starts at
    /// once): the loop waits for it, or starts at once if the clock is already past it.
    pub fn next_start_us(&self) -> Option<u64> {
        self.next_us
    }

    /// Runs one cycle: waits for its start on the grid, plans, performs and completes it.
    pub async fn run_cycle<S, F, IO, D, C>(&mut self, shared: &S, bus: &mut BusMaster<IO, D, C>)
    where
        S: Shared<Controller<F>>,
        F: NorFlash + FlashWindow,
        IO: Read + ReadReady + Write,
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
        let mut end = bus.clock().now_us();
        if let Some(read) = plan.servo_read
            && end + servo_read_budget_us(bus.config(), read) <= due + period
        {
            let result = servo_read(bus, read).await;
            end = bus.clock().now_us();
            shared.with(|c| c.servo_read_done(result));
        }
        if let Some((joint, id)) = plan.health_read
            && end + health_read_budget_us(bus.config()) <= due + period
        {
            let reading = read_health(bus, id).await;
            end = bus.clock().now_us();
            match reading {
                Ok(r) => shared.with(|c| c.health_reading(joint, id, r)),
                Err(BusError::Reply { fault, .. }) => shared.with(|c| c.health_reply_lost(fault)),
                // The UART or the request itself failed: the cycle's own Sync Read reports it.
                Err(_) => {}
            }
            self.timing.health_reads += 1;
        }

        let mut next = due + period;
        let mut missed = 0u32;
        if end > next {
            let behind = (end - next).div_ceil(period);
            missed = behind.min(u32::MAX as u64) as u32;
            next += behind * period;
        }
        self.next_us = Some(next);
        shared.with(|c| {
            c.complete(&plan, outcome, &replies[..plan.reply_count()], late);
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

/// Bytes of the heat and supply Read on the wire: the instruction (header 4, ID, LEN 2, INST,
/// address 2, length 2, CRC 2) and the status with 3 data bytes (11 + 3).
const HEALTH_READ_TX: usize = 14;
const HEALTH_READ_RX: usize = 14;

/// The longest a heat and supply read takes ([`transaction_budget_us`]).
pub fn health_read_budget_us(config: &MasterConfig) -> u64 {
    transaction_budget_us(config, HEALTH_READ_TX, HEALTH_READ_RX)
}

/// The longest one instruction of `tx` bytes and its status of `rx` bytes take: the request's wire
/// time and twice the reply's budget (its wire time and the reply slack; twice, because a garbled
/// reply may hold the receive loop for one more budget before it gives up).
fn transaction_budget_us(config: &MasterConfig, tx: usize, rx: usize) -> u64 {
    let reply = u64::from(config.wire_time_us(rx)) + u64::from(config.reply_slack_us);
    u64::from(config.wire_time_us(tx)) + 2 * reply
}

/// The longest the host's servo read `read` takes ([`transaction_budget_us`]): a Read
/// instruction (14 bytes) and its status (11 + `len`), or a Ping (10) and its status (14).
pub fn servo_read_budget_us(config: &MasterConfig, read: protocol::ServoRead) -> u64 {
    let (tx, rx) = match read.len {
        0 => (10, 14),
        n => (14, 11 + usize::from(n)),
    };
    transaction_budget_us(config, tx, rx)
}

/// Does the host's servo read `read` (a Ping when its length is 0).
async fn servo_read<IO, D, C>(
    bus: &mut BusMaster<IO, D, C>,
    read: protocol::ServoRead,
) -> protocol::ServoReadResult
where
    IO: Read + ReadReady + Write,
    D: DirectionPin,
    C: Clock,
{
    use protocol::ServoReadOutcome as O;
    let lost = |e: BusError| match e {
        BusError::Reply {
            fault: ReplyFault::Timeout,
            ..
        } => O::Timeout,
        _ => O::Corrupt,
    };
    let outcome = if read.len == 0 {
        match bus.ping(read.id).await {
            Ok(p) => O::Ping {
                error: p.error.0,
                model_number: p.model_number,
                firmware: p.firmware,
            },
            Err(e) => lost(e),
        }
    } else {
        let mut buf = [0u8; protocol::MAX_SERVO_READ];
        let out = &mut buf[..usize::from(read.len)];
        match bus.read(read.id, read.addr, out).await {
            Ok(error) => O::Data {
                error: error.0,
                data: heapless::Vec::from_slice(out).unwrap_or_default(),
            },
            Err(e) => lost(e),
        }
    };
    protocol::ServoReadResult {
        request: read,
        outcome,
    }
}

/// Reads servo `id`'s Present Input Voltage (144, 0.1 V) and Present Temperature (146, degC).
async fn read_health<IO, D, C>(
    bus: &mut BusMaster<IO, D, C>,
    id: u8,
) -> Result<protocol::ServoHealth, BusError>
where
    IO: Read + ReadReady + Write,
    D: DirectionPin,
    C: Clock,
{
    let mut b = [0u8; 3];
    bus.read(id, PRESENT_INPUT_VOLTAGE.addr, &mut b).await?;
    Ok(protocol::ServoHealth {
        voltage_dv: u16::from_le_bytes([b[0], b[1]]),
        temperature_c: b[2],
    })
}

/// Performs `plan.action` on the bus.
pub async fn perform<IO, D, C>(
    plan: &CyclePlan,
    bus: &mut BusMaster<IO, D, C>,
    replies: &mut [Reply],
) -> Outcome
where
    IO: Read + ReadReady + Write,
    D: DirectionPin,
    C: Clock,
{
    let (ids, n) = plan.ids();
    let ids = &ids[..n];
    // Goal writes and torque switches carry the platform's servo after the joints'.
    let (all_goals, all_n) = plan.goals_with_platform();
    let all_goals = &all_goals[..all_n];
    let (torque_ids, torque_n) = plan.torque_ids();
    let torque_ids = &torque_ids[..torque_n];
    match plan.action {
        BusAction::Nothing => Outcome::Done(Ok(())),
        BusAction::Cycle => Outcome::Feedback(bus.cycle(all_goals, replies).await),
        BusAction::ReadOnly => Outcome::Feedback(bus.read_feedback(ids, replies).await),
        BusAction::TorqueOn => {
            let mut bytes = [[0u8; 4]; MAX_JOINTS];
            for (b, g) in bytes.iter_mut().zip(all_goals) {
                *b = g.position.to_le_bytes();
            }
            let goals = all_goals.iter().zip(&bytes).map(|(g, b)| (g.id, &b[..]));
            let r = match bus.sync_write(GOAL_POSITION.addr, 4, goals).await {
                Ok(()) => match write_gains(plan, bus).await {
                    Ok(()) => torque(bus, torque_ids, 1).await,
                    Err(e) => Err(e),
                },
                Err(e) => Err(e),
            };
            Outcome::Done(r)
        }
        BusAction::WriteGains => match write_gains(plan, bus).await {
            Ok(()) => Outcome::Feedback(bus.cycle(all_goals, replies).await),
            Err(e) => Outcome::Feedback(Err(e)),
        },
        BusAction::TorqueOff => Outcome::Done(torque(bus, torque_ids, 0).await),
        BusAction::Reboot { joints } => {
            let mut result = Ok(());
            let chosen = ids
                .iter()
                .enumerate()
                .filter(|(j, _)| *j < 32 && joints & (1 << j) != 0);
            for (_, &id) in chosen {
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
        BusAction::PlatformCheck {
            id,
            profile_velocity,
            rest,
            torque,
        } => {
            Outcome::PlatformChecked(check_platform(bus, id, profile_velocity, rest, torque).await)
        }
    }
}

/// The platform servo's set-up: ping, Profile Velocity, Goal Position `rest`, Present Position
/// read, then Torque Enable if the joints hold torque. Any step that fails (no answer, or a status
/// with an error number) fails the check: the servo is not there as set up.
async fn check_platform<IO, D, C>(
    bus: &mut BusMaster<IO, D, C>,
    id: u8,
    profile_velocity: u16,
    rest: u16,
    torque: bool,
) -> Result<u16, BusError>
where
    IO: Read + ReadReady + Write,
    D: DirectionPin,
    C: Clock,
{
    let refused = |e: dynamixel::instruction::StatusError| {
        (e.0 & 0x7F != 0).then_some(BusError::Reply {
            id,
            fault: ReplyFault::Status(e),
        })
    };
    let ping = bus.ping(id).await?;
    if let Some(e) = refused(ping.error) {
        return Err(e);
    }
    let velocity = u32::from(profile_velocity).to_le_bytes();
    if let Some(e) = refused(bus.write(id, PROFILE_VELOCITY.addr, &velocity).await?) {
        return Err(e);
    }
    let goal = u32::from(rest).to_le_bytes();
    if let Some(e) = refused(bus.write(id, GOAL_POSITION.addr, &goal).await?) {
        return Err(e);
    }
    let mut present = [0u8; 4];
    if let Some(e) = refused(bus.read(id, PRESENT_POSITION.addr, &mut present).await?) {
        return Err(e);
    }
    if torque && let Some(e) = refused(bus.write(id, TORQUE_ENABLE.addr, &[1]).await?) {
        return Err(e);
    }
    let ticks = i32::from_le_bytes(present);
    Ok(ticks.clamp(0, i32::from(u16::MAX)) as u16)
}

/// Sync Write of the plan's Position P Gains (joints with stiffness 0 left out; none: no packet).
async fn write_gains<IO, D, C>(
    plan: &CyclePlan,
    bus: &mut BusMaster<IO, D, C>,
) -> Result<(), BusError>
where
    IO: Read + ReadReady + Write,
    D: DirectionPin,
    C: Clock,
{
    if plan.gain_writes().next().is_none() {
        return Ok(());
    }
    let mut bytes = [(0u8, [0u8; 2]); MAX_JOINTS];
    let mut n = 0;
    for (b, (id, p)) in bytes.iter_mut().zip(plan.gain_writes()) {
        *b = (id, p.to_le_bytes());
        n += 1;
    }
    let entries = bytes[..n].iter().map(|(id, b)| (*id, &b[..]));
    bus.sync_write(POSITION_P_GAIN.addr, 2, entries).await
}

async fn torque<IO, D, C>(bus: &mut BusMaster<IO, D, C>, ids: &[u8], on: u8) -> Result<(), BusError>
where
    IO: Read + ReadReady + Write,
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

#[cfg(test)]
mod tests {

    use dynamixel::master::{AutoDirection, MasterConfig};
    use embassy_futures::block_on;

    use super::*;
    use crate::controller::Config;
    use crate::store::nor_double::NorDouble;
    use crate::store::record::CRC32;
    use crate::testkit::SyntheticGait;
    use crate::testkit::clock::JumpClock;

    /// A bus on which nobody answers.
    struct Silent;
    impl embedded_io_async::ErrorType for Silent {
        type Error = core::convert::Infallible;
    }
    impl Read for Silent {
        async fn read(&mut self, _: &mut [u8]) -> Result<usize, Self::Error> {
            core::future::pending().await
        }
    }
    impl embedded_io_async::ReadReady for Silent {
        fn read_ready(&mut self) -> Result<bool, Self::Error> {
            Ok(false)
        }
    }
    impl Write for Silent {
        async fn write(&mut self, buf: &[u8]) -> Result<usize, Self::Error> {
            Ok(buf.len())
        }
        async fn flush(&mut self) -> Result<(), Self::Error> {
            Ok(())
        }
    }

    #[test]
    fn cycles_start_on_the_grid_and_every_skipped_start_is_an_overrun() {
        let table = SyntheticGait::new(10, 1.0).build();
        let mut c = Controller::new(NorDouble::<4>::new(64), 4, Config::default());
        c.upload_begin(0, table.len() as u32).unwrap();
        c.upload_chunk(0, &table).unwrap();
        c.upload_commit(CRC32.checksum(&table)).unwrap();
        let shared = RefCell::new(c);
        // 100 Hz, and a reply budget of 25 ms: each silent cycle takes about 2.5 periods.
        let config = MasterConfig {
            baud: 1_000_000,
            reply_slack_us: 25_000,
        };
        let mut bus = BusMaster::new(Silent, AutoDirection, JumpClock::default(), config);
        let mut l = BusLoop::new();
        let mut starts = vec![];
        let mut overruns = vec![];
        for _ in 0..6 {
            block_on(l.run_cycle(&shared, &mut bus));
            starts.push(l.timing.last_start_us);
            overruns.push(l.timing.overruns);
        }
        for s in &starts {
            assert_eq!(s % 10_000, 0, "start {s} off the 10 ms grid");
        }
        // The grid points skipped between two starts are the overruns the first of them counted.
        for k in 0..5 {
            let skipped = (starts[k + 1] - starts[k]) / 10_000 - 1;
            let counted = overruns[k] - if k == 0 { 0 } else { overruns[k - 1] };
            assert!(skipped >= 1, "cycle {k} overran: {starts:?}");
            assert_eq!(counted, skipped, "cycle {k}: {starts:?}");
        }
        assert_eq!(u64::from(shared.borrow().counters().overruns), overruns[5]);
        // Starts were never late: the loop skips to the next grid point instead of starting late.
        assert_eq!(l.timing.max_late_us, 0);
        // Three silent cycles in Boot make every servo missing: the first one is named.
        assert!(matches!(
            shared.borrow().state(),
            crate::safety::State::Safe(crate::safety::SafeReason::ServoMissing {
                joint: 0,
                id: 1,
                cycles: 3
            })
        ));
    }
}

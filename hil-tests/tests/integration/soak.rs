//! The soak of issue #9 on the real firmware image in the emulator: walking at 100 Hz / 1 Mbps with
//! telemetry every cycle, random noise on the host link and occasional servo overloads.
//!
//! Every 0.5 s of simulated time one bad frame goes to the board, chosen at random: garbage (random
//! non-zero bytes), a valid request with one byte flipped, or one with a byte dropped; each ends with
//! the frame delimiter, so each is exactly one frame the board must reject and count. Every few
//! simulated minutes (half way in a short run) a random servo is overloaded: the board must stop,
//! report `ServoError` with the e-manual's overload bit (bit 5) on that servo's joint, come back to
//! Idle after that servo is rebooted, and walk again. Between faults the board must be walking with
//! no fault. At the end: every bad frame counted, as many faults reported as injected, no chip reset
//! or halt (no crash, no watchdog), the bus cycling at 100 Hz, and the gait kept: the same CRC
//! listed and the gait store's flash bytes identical to those after the upload. Counters are printed
//! every simulated minute, so a partial run still gives figures.
//!
//! `DBOT_SOAK_SIM_S` sets the duration of the long run (default 3600), `DBOT_SOAK_SEED` the random
//! seed (default 9); the short run in the normal suite is 24 s with one overload.

use anyhow::{Context, Result, bail, ensure};
use fastrand::Rng;
use hil_tests::drive::{T, servo_bus, start, start_playing, telemetry, upload_sine_gait};
use hil_tests::gait::JOINTS;
use hil_tests::link::Link;
use hil_tests::{Emulator, Options};
use protocol::client::Client;
use protocol::message::{Direction, FaultKind, RunState, ServoSelect, Status, Steps};
use protocol::{DeviceMessage, Request, Response};
use serde_json::json;
use std::time::{Duration, Instant};

const HIL_BUS: &str = env!("CARGO_BIN_EXE_hil-bus");
/// Hardware Error Status bit 5, overload (e-manual).
const OVERLOAD_BIT: u8 = 1 << 5;
/// memory.x: the gait store spans 0x8_0000..0x20_0000 of the 2 MB flash.
const GAIT_STORE: std::ops::Range<usize> = 0x8_0000..0x20_0000;
const CYCLE_US: u64 = 10_000;
const NOISE_EVERY: Duration = Duration::from_millis(500);

#[test]
fn soak_short_walk_with_link_noise_and_one_servo_overload() -> Result<()> {
    soak("soak_short", 24, 9, None)
}

#[test]
#[ignore = "long: DBOT_SOAK_SIM_S (default 3600) simulated seconds"]
fn soak_long_walk_with_link_noise_and_servo_overloads() -> Result<()> {
    let env = |k: &str, default: u64| -> Result<u64> {
        std::env::var(k)
            .map_or(Ok(default), |v| v.parse())
            .with_context(|| format!("{k} must be a whole number"))
    };
    soak(
        "soak_long",
        env("DBOT_SOAK_SIM_S", 3600)?,
        env("DBOT_SOAK_SEED", 9)?,
        Some((120, 240)),
    )
}

/// What the soak injected and saw.
#[derive(Debug, Default)]
struct Tally {
    garbage: u32,
    flipped: u32,
    dropped: u32,
    overloads: u32,
    reported: u32,
    telemetry: u64,
    max_jitter_us: u64,
    last_record: Option<(u32, u64)>,
    /// Records of cycles before this one (the upload, whose flash erases stall the CPU) are not
    /// part of the soak.
    first_cycle: u32,
}

impl Tally {
    fn bad_frames(&self) -> u32 {
        self.garbage + self.flipped + self.dropped
    }

    /// Cycle-start jitter from the telemetry: how far two consecutive cycles' board times are
    /// from one period apart.
    fn take(&mut self, msgs: impl IntoIterator<Item = DeviceMessage>) {
        for t in telemetry(&msgs.into_iter().collect::<Vec<_>>()) {
            if t.cycle < self.first_cycle {
                continue;
            }
            self.telemetry += 1;
            if let Some((cycle, time)) = self.last_record
                && t.cycle == cycle.wrapping_add(1)
            {
                let dt = t.time_us.saturating_sub(time);
                self.max_jitter_us = self.max_jitter_us.max(dt.abs_diff(CYCLE_US));
            }
            self.last_record = Some((t.cycle, t.time_us));
        }
    }
}

/// Runs the soak for `sim_s` simulated seconds; overloads every `fault_every` (min, max) simulated
/// seconds, or once half way when `None`.
fn soak(test: &str, sim_s: u64, seed: u64, fault_every: Option<(u64, u64)>) -> Result<()> {
    let dir = tempfile::tempdir()?;
    let flash_file = dir.path().join("flash.bin");
    let opts = Options {
        bus: Some(servo_bus(HIL_BUS, JOINTS, 1_000_000)),
        flash_file: Some(flash_file.clone()),
        ..Options::default()
    };
    let Some((board, mut link)) = start(test, opts)? else {
        return Ok(());
    };
    let Some(emu) = board.emulator() else {
        return hil_tests::target::skip(test, "injecting faults needs the emulator");
    };
    let table = upload_sine_gait(&mut link, "soak", None)?;
    let listed = slot0(&mut link)?;
    emu.save_flash()?;
    let store_before = std::fs::read(&flash_file)?[GAIT_STORE].to_vec();
    ensure!(
        store_before.windows(table.len()).any(|w| w == table),
        "the uploaded table is not in the gait store"
    );
    start_playing(&mut link, 0, Direction::Forward, Steps::Continuous)?;

    // Seeded: the run is repeatable from its seed.
    let mut rng = Rng::with_seed(seed);
    let mut client = Client::new();
    let mut tally = Tally::default();
    let s0: Status = link.request(&Request::GetStatus, T)?;
    tally.first_cycle = s0.counters.cycles;
    let (t0, wall0) = (emu.sim_time()?, Instant::now());
    let mut next_fault = match fault_every {
        Some((lo, hi)) => Duration::from_secs(rng.u64(lo..hi)),
        None => Duration::from_secs(sim_s / 2),
    };
    let mut next_report = Duration::from_secs(60);
    println!("soak: {sim_s} s simulated, seed {seed}, gait CRC {listed:#010x}");
    loop {
        let elapsed = emu.sim_time()? - t0;
        if elapsed >= Duration::from_secs(sim_s) {
            break;
        }
        send_bad_frame(&mut link, &mut client, &mut rng, &mut tally)?;
        emu.run_for(NOISE_EVERY)?;
        let s: Status = link.request(&Request::GetStatus, T)?;
        tally.take(link.unsolicited.drain(..));
        ensure!(
            s.fault.is_none() && matches!(s.state, RunState::Walking | RunState::Ramping),
            "at {:.1} s simulated, not walking: {s:?}",
            elapsed.as_secs_f64()
        );
        if elapsed >= next_fault {
            overload_and_recover(emu, &mut link, &mut rng, &mut tally)?;
            next_fault = match fault_every {
                Some((lo, hi)) => elapsed + Duration::from_secs(rng.u64(lo..hi)),
                None => Duration::MAX,
            };
        }
        if elapsed >= next_report {
            report("soak", elapsed, wall0.elapsed(), &s0, &s, &tally);
            next_report += Duration::from_secs(60);
        }
    }

    let s1: Status = link.request(&Request::GetStatus, T)?;
    tally.take(link.unsolicited.drain(..));
    let (sim, wall) = (emu.sim_time()? - t0, wall0.elapsed());
    report("soak done", sim, wall, &s0, &s1, &tally);
    println!("runner stats: {}", emu.stats()?);
    let rejected = s1.counters.rejected_frames - s0.counters.rejected_frames;
    ensure!(
        rejected == tally.bad_frames(),
        "{rejected} frames rejected, {} bad frames sent",
        tally.bad_frames()
    );
    ensure!(
        tally.reported == tally.overloads,
        "{} of {} overloads reported",
        tally.reported,
        tally.overloads
    );
    ensure!(tally.overloads >= 1, "no overload injected in {sim:?}");
    for kind in ["reset", "halted"] {
        let seen = emu.events(kind);
        ensure!(seen.is_empty(), "the chip {kind}: {seen:?}");
    }
    let cycles = s1.counters.cycles - s0.counters.cycles;
    ensure!(
        f64::from(cycles) >= 0.99 * 100.0 * sim.as_secs_f64(),
        "{cycles} bus cycles in {sim:?}"
    );
    ensure!(slot0(&mut link)? == listed, "slot 0's CRC changed");
    emu.save_flash()?;
    let store_after = std::fs::read(&flash_file)?[GAIT_STORE].to_vec();
    ensure!(
        store_after == store_before,
        "the gait store's flash bytes changed during the soak"
    );
    Ok(())
}

/// One frame the board must reject: garbage, or a valid request with a byte flipped or dropped.
/// Never a zero byte inside and always the delimiter at the end, so it is exactly one frame.
fn send_bad_frame(
    link: &mut Link,
    client: &mut Client,
    rng: &mut Rng,
    t: &mut Tally,
) -> Result<()> {
    let frame = match rng.u8(..3) {
        0 => {
            t.garbage += 1;
            let len = rng.usize(1..40);
            let mut f: Vec<u8> = (0..len).map(|_| rng.u8(1..)).collect();
            f.push(0);
            f
        }
        kind => {
            let request = [Request::GetStatus, Request::ListGaits][rng.usize(..2)].clone();
            let (_, mut f) = client
                .request_frame(&request)
                .map_err(|e| anyhow::anyhow!("cannot encode {request:?}: {e:?}"))?;
            ensure!(f.last() == Some(&0) && f.len() > 2, "frame {f:02x?}");
            let i = rng.usize(..f.len() - 1);
            if kind == 1 {
                t.flipped += 1;
                let old = f[i];
                let new = loop {
                    let b = old ^ rng.u8(1..);
                    if b != 0 {
                        break b;
                    }
                };
                f[i] = new;
            } else {
                t.dropped += 1;
                f.remove(i);
            }
            f
        }
    };
    debug_assert!(frame[..frame.len() - 1].iter().all(|&b| b != 0));
    link.send_raw(&frame)
}

/// Overloads a random servo, checks the report (state Fault, its joint, the overload bit), reboots
/// that servo, waits for Idle and plays again.
fn overload_and_recover(
    emu: &Emulator,
    link: &mut Link,
    rng: &mut Rng,
    t: &mut Tally,
) -> Result<()> {
    let id = rng.u8(1..=JOINTS as u8);
    let joint = id - 1; // sine_gait maps joint j to servo ID j + 1
    emu.bus_control(json!({ "overload": id }))?;
    t.overloads += 1;
    let deadline = emu.sim_time()? + Duration::from_secs(2);
    loop {
        emu.run_for(Duration::from_millis(20))?;
        let s: Status = link.request(&Request::GetStatus, T)?;
        if let Some(f) = s.fault {
            ensure!(
                f.joint == Some(joint) && s.state == RunState::Fault,
                "overload of servo {id} (joint {joint}) reported as {s:?}"
            );
            if let FaultKind::ServoError { bits } = f.kind
                && bits & OVERLOAD_BIT != 0
            {
                t.reported += 1;
                break;
            }
        }
        if emu.sim_time()? > deadline {
            bail!("overload of servo {id} not reported with its bit within 2 s: {s:?}");
        }
    }
    let r: Response = link.request(
        &Request::RebootServos {
            servos: ServoSelect::Joint(joint),
        },
        T,
    )?;
    ensure!(r == Response::Ack, "RebootServos: {r:?}");
    let deadline = emu.sim_time()? + Duration::from_secs(2);
    loop {
        emu.run_for(Duration::from_millis(50))?;
        let s: Status = link.request(&Request::GetStatus, T)?;
        if s.state == RunState::Idle && s.fault.is_none() {
            break;
        }
        if emu.sim_time()? > deadline {
            bail!("not Idle 2 s after rebooting servo {id}: {s:?}");
        }
    }
    t.take(link.unsolicited.drain(..));
    start_playing(link, 0, Direction::Forward, Steps::Continuous)
}

fn report(what: &str, sim: Duration, wall: Duration, s0: &Status, s: &Status, t: &Tally) {
    let (a, b) = (&s0.counters, &s.counters);
    println!(
        "{what}: {:.0} s simulated in {:.0} s wall ({:.3} x real time): cycles {}, missed deadlines \
         {}, max jitter {} us (telemetry, {} records), bus timeouts {}, CRC errors {}, rejected \
         frames {} of {} bad (garbage {}, flipped {}, dropped {}), telemetry dropped {}, overloads \
         {} injected / {} reported",
        sim.as_secs_f64(),
        wall.as_secs_f64(),
        sim.as_secs_f64() / wall.as_secs_f64(),
        b.cycles - a.cycles,
        b.missed_deadlines - a.missed_deadlines,
        t.max_jitter_us,
        t.telemetry,
        b.bus_timeouts - a.bus_timeouts,
        b.crc_errors - a.crc_errors,
        b.rejected_frames - a.rejected_frames,
        t.bad_frames(),
        t.garbage,
        t.flipped,
        t.dropped,
        b.telemetry_dropped - a.telemetry_dropped,
        t.overloads,
        t.reported,
    );
}

/// The table CRC listed for slot 0 (the table's own stored CRC).
fn slot0(link: &mut Link) -> Result<u32> {
    let r: Response = link.request(&Request::ListGaits, T)?;
    let Response::Slots(slots) = r else {
        bail!("ListGaits: {r:?}");
    };
    slots
        .iter()
        .find(|s| s.slot == 0)
        .and_then(|s| s.gait.map(|g| g.crc))
        .context("slot 0 holds no gait")
}

//! Streaming setpoint latency of the real firmware image, on the emulator's simulated clock: from
//! the moment the USB OUT packet that completes a setpoint's frame is handed to the emulated chip
//! (the board's view of "the host sent it") to the first start bit of the Sync Write whose goals
//! carry it (on the bus). Issue #10's bound: at most two bus cycles, at 100 Hz and at 200 Hz.
//!
//! Independent truth: arrival times come from the runner's USB trace and the setpoint is
//! identified by decoding the traced host bytes with the protocol crate; bus times and goals come
//! from the traced wire bytes, parsed with the dynamixel crate's parser, not from the firmware's
//! own proprioception records. Every setpoint sets all 22 joints to its own angle, 50e-4 rad
//! (3.3 servo ticks) from the previous one, and the test gait's calibration (zero 2048 ticks, sign
//! +, no torque bias) maps it to ticks = 2048 + angle * 4096 / (2 pi).
//!
//! Setpoints must land at every phase of the bus cycle, or the worst case (just after a cycle
//! has taken its goals) would go unseen. The host's bytes enter simulated time only between the
//! runner's 1 ms run slices, which restart after every bus burst, so a host alone reaches only a
//! few phases. The test therefore sweeps the runner's USB OUT turnaround (the simulated time from
//! the host's bytes being there to the packet landing) over one cycle period in hundredths. The
//! phase each setpoint really landed at is taken from the traces (arrival minus the start of the
//! last Sync Write before it) and must cover every tenth of the cycle.

use anyhow::{Context, Result, bail, ensure};
use hil_tests::bus_trace::{goal_writes_of_whole_bursts, unbroken_packets};
use hil_tests::drive::{T, start_playing, start_with_servos};
use hil_tests::gait::{JOINTS, sine_gait, upload};
use hil_tests::link::Link;
use hil_tests::{Emulator, TracedBurst, UsbOut};
use protocol::{
    Client, DeviceMessage, FrameAccumulator, HostMessage, JointSetpoint, MAX_CHUNK_LEN,
    MAX_FRAME_LEN, Request, Response, RunState, Setpoint, Status, Steps, StreamConfig,
};
use std::collections::HashMap;
use std::time::{Duration, Instant};

const HIL_BUS: &str = env!("CARGO_BIN_EXE_hil-bus");
/// Setpoints measured per rate.
const SAMPLES: u32 = 100;
/// Sequence number of the first measured setpoint.
const SEQ0: u32 = 1000;
/// Angle of setpoint k: (ANGLE0 + ANGLE_STEP * k) * 1e-4 rad, within the gait's +-1.5 rad.
const ANGLE0: i16 = 100;
const ANGLE_STEP: i16 = 50;

fn angle(k: u32) -> i16 {
    ANGLE0 + ANGLE_STEP * k as i16
}

/// Goal ticks of an angle (1e-4 rad) under the test gait's calibration.
fn ticks(angle: i16) -> i32 {
    2048 + (f64::from(angle) * 1e-4 * 4096.0 / std::f64::consts::TAU).round() as i32
}

/// One measured setpoint.
#[derive(Debug, Clone, Copy)]
struct Sample {
    /// Simulated time the USB OUT packet completing its frame reached the chip.
    arrival: Duration,
    /// First start bit of the Sync Write carrying it.
    on_bus: Duration,
    /// Arrival minus the start of the last Sync Write before it, in cycles (0..1).
    phase: f64,
    /// When the host's bytes reached the runner, out of the pty (before the chip takes them).
    runner: Duration,
    /// Simulated time just before the host wrote it to the pty.
    before_write: Duration,
}

#[test]
fn setpoint_latency_at_100_hz_1_mbps() -> Result<()> {
    check("stream_latency_100", 1_000_000, 100, true)
}

#[test]
fn setpoint_latency_at_200_hz_4_mbps() -> Result<()> {
    check("stream_latency_200", 4_000_000, 200, true)
}

/// 2 Mbit/s would fit a 22-servo cycle in 5 ms on paper (622 bytes = 3.1 ms, plus 22 servo
/// turnarounds), but while streaming with feedback every cycle the link task's work makes cycle
/// starts up to about 1 ms late and about one cycle in 16 overruns (skipped), so 200 Hz runs at
/// 4 Mbit/s. Kept to show it: `cargo test -p hil-tests --test integration stream_latency:: -- --ignored`.
#[test]
#[ignore = "cycles overrun at 200 Hz / 2 Mbit/s while streaming (see docs/performance.md)"]
fn setpoint_latency_at_200_hz_2_mbps() -> Result<()> {
    check("stream_latency_200_2M", 2_000_000, 200, false)
}

/// Measures at `baud` and `cycle_hz`; with `keeps_rate`, the firmware must also not have skipped a
/// cycle start (the bound is in cycles of the configured rate).
fn check(test: &str, baud: u32, cycle_hz: u16, keeps_rate: bool) -> Result<()> {
    let Some((board, mut link)) = start_with_servos(test, HIL_BUS, JOINTS, baud)? else {
        return Ok(());
    };
    let Some(emu) = board.emulator() else {
        return hil_tests::target::skip(test, "the USB and bus traces need the emulator");
    };
    stand_and_stream(&mut link, baud, cycle_hz)?;
    let before: Status = link.request(&Request::GetStatus, T)?;
    let (samples, starts) = measure(emu, &mut link, cycle_hz)?;
    let after: Status = link.request(&Request::GetStatus, T)?;
    let r: Response = link.request(&Request::LeaveStreaming, T)?;
    ensure!(r == Response::Ack, "LeaveStreaming answered {r:?}");

    let period = 1.0 / f64::from(cycle_hz);
    let lat: Vec<f64> = samples
        .iter()
        .map(|s| (s.on_bus - s.arrival).as_secs_f64() / period)
        .collect();
    let (min, mean, max) = stats(&lat);
    let ms = |f: &dyn Fn(&Sample) -> Duration| -> (f64, f64, f64) {
        stats(
            &samples
                .iter()
                .map(|s| f(s).as_secs_f64() * 1e3)
                .collect::<Vec<_>>(),
        )
    };
    let pty = ms(&|s| s.runner.saturating_sub(s.before_write));
    let mut deciles = [0usize; 10];
    for s in &samples {
        deciles[((s.phase * 10.0) as usize).min(9)] += 1;
    }
    println!(
        "{cycle_hz} Hz, {baud} bit/s, {} setpoints, simulated time:\n  \
         USB packet on the chip -> Sync Write start: min {min:.3} / mean {mean:.3} / max {max:.3} \
         cycles = {:.2} / {:.2} / {:.2} ms\n  \
         arrivals on the chip per tenth of the cycle after a Sync Write start: {deciles:?}\n  \
         host's write -> bytes at the runner (wall-clock pty transit, the emulator running on): \
         {:.2} / {:.2} / {:.2} ms",
        samples.len(),
        min * period * 1e3,
        mean * period * 1e3,
        max * period * 1e3,
        pty.0,
        pty.1,
        pty.2,
    );
    // Cycles that did not start one period after the previous one (late starts, overruns).
    let irregular: Vec<f64> = starts
        .windows(2)
        .map(|w| (w[1] - w[0]).as_secs_f64() / period)
        .filter(|c| (c - 1.0).abs() > 0.05)
        .collect();
    println!(
        "  {} cycles traced, {} not one period after the previous (in periods: {irregular:.3?}); \
         firmware counters over the run: missed deadlines +{}, servo timeouts +{}",
        starts.len(),
        irregular.len(),
        after.counters.missed_deadlines - before.counters.missed_deadlines,
        after.counters.bus_timeouts - before.counters.bus_timeouts,
    );
    for s in samples
        .iter()
        .filter(|s| s.on_bus - s.arrival > Duration::from_secs_f64(period))
    {
        println!(
            "  over one cycle: arrived at phase {:.3}, on the bus {:.3} cycles later",
            s.phase,
            (s.on_bus - s.arrival).as_secs_f64() / period
        );
    }
    ensure!(
        deciles.iter().all(|&n| n > 0),
        "setpoints arrived in too few phases of the cycle to show the worst case: {deciles:?}"
    );
    ensure!(min > 0.0, "a setpoint was on the bus before it arrived");
    let missed = after.counters.missed_deadlines - before.counters.missed_deadlines;
    ensure!(
        !keeps_rate || missed == 0,
        "{missed} cycle starts missed while streaming at {cycle_hz} Hz"
    );
    ensure!(
        max <= 2.0,
        "a setpoint took {max:.3} cycles to reach the bus (bound: 2)"
    );
    Ok(())
}

fn stats(v: &[f64]) -> (f64, f64, f64) {
    let min = v.iter().cloned().fold(f64::INFINITY, f64::min);
    let max = v.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    (min, v.iter().sum::<f64>() / v.len() as f64, max)
}

/// Uploads a test gait, plays one step at `cycle_hz` so the board stands in its posture, and
/// enters streaming with feedback every cycle.
fn stand_and_stream(link: &mut Link, baud: u32, cycle_hz: u16) -> Result<()> {
    let (builder, table) = sine_gait("latency", 40, 0.2)?;
    let r = upload(link, 0, &builder, &table, MAX_CHUNK_LEN, T)?;
    ensure!(matches!(r, Response::Committed { .. }), "{r:?}");
    // Playback telemetry off: only the streaming records matter here.
    let r: Response = link.request(&Request::SetTelemetry { every: 0 }, T)?;
    ensure!(r == Response::Ack, "SetTelemetry answered {r:?}");
    let r: Response = link.request(&Request::SetBus { baud, cycle_hz }, T)?;
    ensure!(r == Response::Ack, "SetBus answered {r:?}");
    start_playing(link, 0, protocol::Direction::Forward, Steps::Count(1))?;
    let started = Instant::now();
    loop {
        let s: Status = link.request(&Request::GetStatus, T)?;
        ensure!(s.fault.is_none(), "fault before streaming: {s:?}");
        if s.state == RunState::Standing {
            break;
        }
        if started.elapsed() > Duration::from_secs(120) {
            bail!("the board did not stand within 120 s (wall): {s:?}");
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    // Proprioception is gated by the telemetry setting, not by StreamConfig::feedback_every
    // (which the firmware stores but does not use: controller/feedback.rs, queue_telemetry).
    let r: Response = link.request(&Request::SetTelemetry { every: 1 }, T)?;
    ensure!(r == Response::Ack, "SetTelemetry answered {r:?}");
    // A long timeout: a host stalled by a loaded machine must not end the stream; the rule itself
    // is tested in safety.rs and python/tests/test_closed_loop.py.
    let r: Response = link.request(
        &Request::EnterStreaming(StreamConfig {
            timeout_cycles: 200,
            feedback_every: 1,
        }),
        T,
    )?;
    ensure!(r == Response::Ack, "EnterStreaming answered {r:?}");
    // The board moves a goal toward a setpoint by at most the servo's step per cycle
    // (firmware::goal_step: 18 ticks on an MX-28 at 200 Hz) and the standing posture is up to
    // 0.2 rad (130 ticks) from the first measured setpoint: settle one ANGLE_STEP (3.3 ticks)
    // short of it first, so that every measured setpoint reaches the bus in one cycle.
    let settle = Setpoint {
        seq: SEQ0 - 1,
        joints: (0..JOINTS)
            .map(|_| JointSetpoint {
                angle: ANGLE0 - ANGLE_STEP,
                torque: None,
            })
            .collect(),
    };
    let mut buf = [0u8; MAX_FRAME_LEN];
    let frame = Client::encode_setpoint(&settle, &mut buf)
        .map_err(|e| anyhow::anyhow!("cannot encode the settling setpoint: {e:?}"))?;
    link.send_raw(frame)?;
    record_where(link, |p| p.setpoint_seq == SEQ0 - 1 && p.setpoint_age >= 40)
        .context("the settling setpoint was not held for 40 cycles")?;
    link.unsolicited.clear();
    Ok(())
}

/// Waits for a proprioception record that satisfies `want`.
fn record_where(
    link: &mut Link,
    want: impl Fn(&protocol::Proprioception) -> bool,
) -> Result<protocol::Proprioception> {
    let started = Instant::now();
    while started.elapsed() < Duration::from_secs(60) {
        match link.next_message(Duration::from_secs(60))? {
            Some(DeviceMessage::Proprioception(p)) if want(&p) => return Ok(p),
            // Playback telemetry of the standing cycles before streaming began may still come.
            Some(DeviceMessage::Proprioception(_)) | Some(DeviceMessage::Telemetry(_)) => {}
            Some(other) => bail!("unexpected message while streaming: {other:?}"),
            None => break,
        }
    }
    bail!("no matching proprioception within 60 s (wall)")
}

/// The samples, and the start of every traced Sync Write.
fn measure(emu: &Emulator, link: &mut Link, cycle_hz: u16) -> Result<(Vec<Sample>, Vec<Duration>)> {
    emu.usb_trace_start()?;
    emu.bus_trace_start()?;
    // So that the first setpoint arrives after a traced cycle start.
    for _ in 0..2 {
        record_where(link, |_| true)?;
    }
    let period = Duration::from_secs(1) / u32::from(cycle_hz);
    let mut before_write = HashMap::new();
    for k in 0..SAMPLES {
        // 37 and 100 are coprime: the delays visit every hundredth of a period once, out of order.
        emu.set_usb_out_delay(period.mul_f64(f64::from((k * 37) % SAMPLES) / f64::from(SAMPLES)))?;
        let seq = SEQ0 + k;
        let sp = Setpoint {
            seq,
            joints: (0..JOINTS)
                .map(|_| JointSetpoint {
                    angle: angle(k),
                    torque: None,
                })
                .collect(),
        };
        let mut buf = [0u8; MAX_FRAME_LEN];
        let frame = Client::encode_setpoint(&sp, &mut buf)
            .map_err(|e| anyhow::anyhow!("cannot encode setpoint {seq}: {e:?}"))?;
        before_write.insert(seq, emu.sim_time()?);
        link.send_raw(frame)?;
        // One new setpoint per cycle: the next is sent only after a cycle has started with this
        // one (age >= 1), else it would replace this one before it reached the bus (by design).
        record_where(link, |p| p.setpoint_seq == seq && p.setpoint_age >= 1)
            .with_context(|| format!("setpoint {seq} never applied"))?;
    }
    // The last setpoint's Sync Write is on the wire once its record came; stop the traces.
    let usb = emu.usb_trace_stop()?;
    let bursts = emu.bus_trace_stop_bytes()?;
    // Every request left the pin unbroken: streaming at 4 Mbit/s used to cut a Sync Write when an
    // interrupt delayed the UART's FIFO refill (firmware/src/rp.rs, BusUart).
    let unbroken = unbroken_packets(&bursts).context("the board's requests while streaming")?;
    println!(
        "  {} bursts traced, {unbroken} Sync Writes, none with a gap inside",
        bursts.len()
    );
    let arrivals = arrivals(&usb)?;
    let writes = sync_writes(&bursts)?;
    emu.set_usb_out_delay(Duration::from_micros(10))?;
    ensure!(
        writes.len() > 10,
        "only {} Sync Writes traced",
        writes.len()
    );
    let samples = (0..SAMPLES)
        .map(|k| {
            let seq = SEQ0 + k;
            let (runner, arrival) = *arrivals
                .get(&seq)
                .with_context(|| format!("setpoint {seq} not in the USB trace"))?;
            let want = ticks(angle(k));
            let carries = |goals: &[i32]| goals.iter().all(|&g| (g - want).abs() <= 1);
            let Some((on_bus, _)) = writes
                .iter()
                .find(|(start, goals)| *start >= arrival && carries(goals))
            else {
                bail!("setpoint {seq} ({want} ticks) never in a Sync Write after it arrived");
            };
            // The cycle it arrived in: the last Sync Write that started before it.
            let Some((cycle_start, before)) = writes.iter().rev().find(|(s, _)| *s < arrival)
            else {
                bail!("setpoint {seq} arrived before the first traced cycle");
            };
            ensure!(
                !carries(before),
                "setpoint {seq} was on the bus before it arrived"
            );
            Ok(Sample {
                arrival,
                on_bus: *on_bus,
                phase: (arrival - *cycle_start).as_secs_f64() / period.as_secs_f64(),
                runner,
                before_write: before_write[&seq],
            })
        })
        .collect::<Result<Vec<_>>>()?;
    Ok((samples, writes.iter().map(|w| w.0).collect()))
}

/// When each setpoint's frame reached the runner (the host's bytes out of the pty) and when it
/// was complete on the chip (the USB OUT packet that carried its last byte), by sequence number.
fn arrivals(trace: &[UsbOut]) -> Result<HashMap<u32, (Duration, Duration)>> {
    // The host's writes as (end of their bytes in the OUT stream, time they reached the runner).
    let mut host = Vec::new();
    let mut host_end = 0usize;
    let mut acc = FrameAccumulator::new();
    let mut chip_bytes = 0usize;
    let mut out = HashMap::new();
    for e in trace {
        let (at, data) = match e {
            UsbOut::FromHost { at, len } => {
                host_end += len;
                host.push((host_end, *at));
                continue;
            }
            UsbOut::ToChip { at, data } => (*at, data),
        };
        for &b in data {
            chip_bytes += 1;
            match acc.push_message::<HostMessage>(b) {
                Some(Ok(HostMessage::Setpoint(sp))) => {
                    let Some(&(_, runner)) = host.iter().find(|(end, _)| *end >= chip_bytes) else {
                        bail!("setpoint {} on the chip before the host sent it", sp.seq);
                    };
                    out.insert(sp.seq, (runner, at));
                }
                Some(Ok(other)) => bail!("unexpected host message in the trace: {other:?}"),
                Some(Err(e)) => bail!("undecodable host frame in the USB trace: {e:?}"),
                None => {}
            }
        }
    }
    Ok(out)
}

/// Every Sync Write of Goal Position on the wire, in whole bursts ([`goal_writes_of_whole_bursts`]),
/// each for all the joints: start
/// of its burst and the goal of each servo, in ticks, in ID order.
fn sync_writes(bursts: &[TracedBurst]) -> Result<Vec<(Duration, Vec<i32>)>> {
    goal_writes_of_whole_bursts(bursts)?
        .into_iter()
        .map(|(start, goals)| {
            ensure!(
                goals.len() == JOINTS,
                "Sync Write for {} servos, expected {JOINTS}",
                goals.len()
            );
            Ok((start, goals.into_iter().map(|g| g.1).collect()))
        })
        .collect()
}

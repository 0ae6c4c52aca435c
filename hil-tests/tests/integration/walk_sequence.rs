//! Issue 28's run on the emulated board: straight, a curve, backward and stop as one walk of
//! queued gaits on the release firmware image with the virtual servo chain, checked in the board's
//! own units (bus cycles, the step and slice its telemetry reports, the state changes its defmt
//! log names), never the host's clock.
//!
//! The gaits are the planner's, as `dbot table --plan` builds them without the torque bias (so a
//! goal is the table's angle): the servo-safe tripod (2.5 s per step) and the same tripod turning
//! 6 deg per step (lab's walk_sequence test: its slice 0 stays within one bus cycle of the
//! straight gait's at every joint, `protocol::switch`), 50 slices each. Played: 1 step straight
//! forward, then (queued) 2 steps of the curve, then (queued, endless) straight backward, stopped
//! by `Stop` as soon as the status shows it playing.
//!
//! Independent truths: a step of 2.5 s at the default 100 Hz bus cycle is 250 cycles (hand); a goal
//! at slice s lies between the table's angles at s and its neighbours (linear interpolation), to
//! half a servo tick plus the telemetry unit; backward playback runs a table's slices downwards; the
//! state diagram of firmware/src/safety/mod.rs says which changes a queued switch and a stop make.

use std::time::Duration;

use anyhow::{Context, Result, ensure};
use hil_tests::drive::{T, poll_walking, start_playing, start_with_servos, telemetry};
use hil_tests::gait::{JOINTS, upload_table};
use hil_tests::state_log::{UPLOAD_AND_WALK, ensure_state_changes, state_lines};
use planner::gait::{StepParams, Turn};
use protocol::message::{Direction, RunState, Status, Steps};
use protocol::{MAX_CHUNK_LEN, PlayCommand, QueueCommand, Request, Response, Telemetry};

const HIL_BUS: &str = env!("CARGO_BIN_EXE_hil-bus");
const SLICES: usize = 50;
/// Bus cycles per step: 2.5 s at 100 Hz.
const STEP_CYCLES: usize = 250;
/// Half a servo position tick (4096 per turn) plus the telemetry's 1e-4 rad unit.
const SLACK_RAD: f64 = std::f64::consts::PI / 4096.0 + 1e-4;

/// One gait's angles at the servo joints, `[slice][table joint]`, rad.
struct Angles(Vec<Vec<f64>>);

impl Angles {
    /// How far `goal` (table joint order, rad) lies outside the hull of slices s-1, s, s+1.
    fn miss(&self, s: usize, goal: &[f64]) -> f64 {
        let n = self.0.len();
        let around = [
            &self.0[(s + n - 1) % n],
            &self.0[s % n],
            &self.0[(s + 1) % n],
        ];
        let mut worst = 0.0f64;
        for (j, g) in goal.iter().enumerate() {
            let lo = around.iter().map(|a| a[j]).fold(f64::INFINITY, f64::min) - SLACK_RAD;
            let hi = around
                .iter()
                .map(|a| a[j])
                .fold(f64::NEG_INFINITY, f64::max)
                + SLACK_RAD;
            worst = worst.max((lo - g).max(g - hi).max(0.0));
        }
        worst
    }
}

/// The plan of `params` as a table without torques, and its servo joints' angles.
fn gait(params: &StepParams, name: &str) -> Result<(Vec<u8>, Angles)> {
    let model = planner::model::builtin("drosophibot2").context("the built-in model")?;
    let plan = planner::plan::plan(&model, params).with_context(|| format!("planning {name}"))?;
    let table = planner::plan::table::step_table(&plan, None, name)
        .map_err(|e| anyhow::anyhow!("the table of {name}: {e}"))?;
    let joints = planner::plan::table::servo_joints(&model);
    ensure!(joints.len() == JOINTS, "{} servo joints", joints.len());
    let angles = plan
        .q
        .iter()
        .map(|q| joints.iter().map(|&j| q[j]).collect())
        .collect();
    Ok((table, Angles(angles)))
}

fn goals(t: &Telemetry) -> Vec<f64> {
    t.joints
        .iter()
        .map(|f| f64::from(f.commanded) * 1e-4)
        .collect()
}

#[test]
fn straight_then_a_curve_then_backward_then_stop_switching_at_step_boundaries() -> Result<()> {
    let mut straight = StepParams::preset("servo-safe", "drosophibot2").context("preset")?;
    straight.slices = SLICES;
    let mut turn = straight.clone();
    Turn {
        turn_deg: Some(6.0),
        radius_m: None,
    }
    .apply(&mut turn)
    .map_err(|e| anyhow::anyhow!("the turn: {e}"))?;
    let (straight_table, straight_q) = gait(&straight, "straight")?;
    let (turn_table, turn_q) = gait(&turn, "curve")?;

    let Some((board, mut link)) = start_with_servos("walk_sequence", HIL_BUS, JOINTS, 1_000_000)?
    else {
        return Ok(());
    };
    for (slot, table) in [(0u8, &straight_table), (1, &turn_table)] {
        let r = upload_table(&mut link, slot, table, MAX_CHUNK_LEN, T)?;
        ensure!(
            matches!(r, Response::Committed { .. }),
            "slot {slot}: {r:?}"
        );
    }
    let r: Response = link.request(&Request::SetTelemetry { every: 1 }, T)?;
    ensure!(r == Response::Ack, "{r:?}");
    start_playing(&mut link, 0, Direction::Forward, Steps::Count(1))?;
    for (slot, direction, steps) in [
        (1u8, Direction::Forward, Steps::Count(2)),
        (0, Direction::Backward, Steps::Continuous),
    ] {
        let q = QueueCommand(PlayCommand::new(slot, direction, 1000, steps));
        let r: Response = link.request(&Request::QueueGait(q), T)?;
        ensure!(r == Response::Ack, "queueing slot {slot}: {r:?}");
    }
    let mut tele: Vec<Telemetry> = Vec::new();
    let mut stopped_in = None;
    let mut stood = false;
    // Wall-clock bound only against a wedged emulator: 20 s of board time at 0.05 x real time.
    for _ in 0..4000 {
        let s = poll_walking(&mut link, &mut tele)?;
        let backward = s
            .playback
            .is_some_and(|p| p.slot == 0 && p.direction == Direction::Backward);
        if backward && stopped_in.is_none() {
            let r: Response = link.request(&Request::Stop, T)?;
            ensure!(r == Response::Ack, "Stop: {r:?}");
            stopped_in = s.playback.map(|p| p.step);
        }
        if stopped_in.is_some() && s.state == RunState::Standing {
            tele.extend(telemetry(&link.collect(Duration::from_millis(300))?));
            stood = true;
            break;
        }
    }
    ensure!(
        stood,
        "the board did not stand again after Stop (telemetry: {} records)",
        tele.len()
    );
    let stopped_in = stopped_in.context("the backward gait was never seen playing")?;
    let s: Status = link.request(&Request::GetStatus, T)?;
    ensure!(s.fault.is_none(), "fault after the run: {s:?}");

    // The segments by the board's step count: 0 straight forward, 1 and 2 the curve, 3 on
    // straight backward up to the step the stop ended (the standing records keep its count).
    let last = tele.iter().map(|t| t.step).max().context("no telemetry")?;
    let walk_end = last - 1;
    ensure!(
        walk_end >= 3,
        "the walk ended after step {walk_end}, before the backward gait"
    );
    let segment = |step: u32| match step {
        0 => ("straight forward", &straight_q, Direction::Forward),
        1 | 2 => ("the curve", &turn_q, Direction::Forward),
        _ => ("straight backward", &straight_q, Direction::Backward),
    };
    // The ramp ends at the straight gait's slice 0: records of step 0 count from the first one
    // past slice 0, whose goals the table gives.
    let first = tele
        .iter()
        .position(|t| t.slice != 0)
        .context("the walk never left slice 0")?;
    let walked = &tele[first..];
    // Every bus cycle's record from the walk on, none skipped: the cycle counter is the clock
    // here (while the board boots after the first upload it drops a few, before the walk).
    let gaps: Vec<(u32, u32)> = walked
        .windows(2)
        .filter(|w| w[1].cycle != w[0].cycle + 1)
        .map(|w| (w[0].cycle, w[1].cycle))
        .collect();
    ensure!(
        gaps.is_empty(),
        "telemetry skipped cycles (from, to): {gaps:?}"
    );
    let mut worst = 0.0f64;
    let mut other = 0.0f64;
    for (i, t) in walked.iter().enumerate() {
        let g = goals(t);
        if t.step > walk_end {
            // Standing after the stop: held at the backward gait's boundary posture, slice 0.
            let m = straight_q.miss(0, &g);
            ensure!(
                m == 0.0,
                "cycle {}: standing {m:.4} rad off slice 0",
                t.cycle
            );
            continue;
        }
        let (name, q, direction) = segment(t.step);
        let m = q.miss(t.slice.into(), &g);
        worst = worst.max(m);
        ensure!(
            m == 0.0,
            "cycle {} (step {}, slice {}): a goal {m:.4} rad outside {name}'s slices",
            t.cycle,
            t.step,
            t.slice
        );
        if name == "the curve" {
            other = other.max(straight_q.miss(t.slice.into(), &g));
        }
        // Within a step the slices run up (forward) or down (backward).
        if let Some(prev) = i.checked_sub(1).map(|k| &walked[k])
            && prev.step == t.step
        {
            let ordered = match direction {
                Direction::Forward => t.slice >= prev.slice,
                Direction::Backward => t.slice <= prev.slice || prev.slice == 0,
            };
            ensure!(
                ordered,
                "cycle {}: {name} went from slice {} to {}",
                t.cycle,
                prev.slice,
                t.slice
            );
        }
    }
    // The check tells the gaits apart: the curve's goals leave the straight gait's slices.
    println!(
        "goals off their gait's slices by at most {worst:.5} rad; the curve's off the straight \
         gait's by up to {other:.4} rad"
    );
    ensure!(
        other > 0.005,
        "the curve's goals are the straight gait's ({other:.4} rad)"
    );

    // Each boundary (a switch or not) at the end of a whole step: the last record of a step is
    // its last slice (forward: 49; backward, running down: 0), the next one slice 0 of the next
    // step; a step lasts 250 cycles, +-1 for the cycle a boundary lands in (the clock advances
    // by the timer's measured cycle time).
    for k in 1..=last {
        let at = walked
            .iter()
            .position(|t| t.step == k)
            .with_context(|| format!("no record of step {k}"))?;
        let (before, after) = (&walked[at - 1], &walked[at]);
        let (name, _, direction) = segment(k - 1);
        let end = match direction {
            Direction::Forward => (SLICES - 1) as u16,
            Direction::Backward => 0,
        };
        ensure!(
            before.slice == end && after.slice == 0,
            "step {} of {name} ended at slice {} (next: slice {}), not at the boundary",
            k - 1,
            before.slice,
            after.slice
        );
        if k >= 2 {
            let cycles = tele.iter().filter(|t| t.step == k - 1).count();
            ensure!(
                cycles.abs_diff(STEP_CYCLES) <= 1,
                "step {} of {name} took {cycles} cycles, not {STEP_CYCLES}",
                k - 1
            );
        }
    }

    // The state changes, in order, from the firmware's own log: the queued switches and the
    // steps' ends keep it walking (Walking -> Walking is not a change), the stop comes mid-step
    // and the board stands at the end of that step.
    let Some(emu) = board.emulator() else {
        println!("a real board: its state log is not read here (no defmt stream)");
        return Ok(());
    };
    let lines = state_lines(emu);
    let want = [
        &UPLOAD_AND_WALK[..],
        &[
            "state Walking -> Stopping on Event(Stop)",
            "state Stopping -> Standing on Event(EndOfStep)",
        ],
    ]
    .concat();
    ensure_state_changes(&lines, &want)?;
    // The stop arrived in the step the board then finished: its firmware time lies in that step.
    let stop_s = lines
        .iter()
        .find(|t| t.contains("Walking -> Stopping"))
        .and_then(|t| t.split_whitespace().next()?.parse::<f64>().ok())
        .context("the stop's log line has no firmware time")?;
    let stop_step = tele
        .iter()
        .rfind(|t| (t.time_us as f64) * 1e-6 <= stop_s)
        .map(|t| t.step)
        .context("no record before the stop")?;
    println!(
        "Stop sent in step {stopped_in} (status), logged at {stop_s:.6} s in step {stop_step}; \
         the walk ended after step {walk_end}"
    );
    ensure!(
        stop_step == walk_end,
        "the stop came in step {stop_step}, the walk ended after step {walk_end}"
    );
    Ok(())
}

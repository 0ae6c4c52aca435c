//! `dbot run`: plays a stored gait, following its steps with a progress bar until the robot stands.
//! Ctrl-C while following stops the walk at the end of the step, waits until the robot stands and
//! exits non-zero; it never leaves the robot walking.

use std::time::Duration;

use anyhow::{Context, bail};
use indicatif::{ProgressBar, ProgressStyle};
use protocol::RunState;

use crate::args::board::BoardArgs;
use crate::common::interrupt;
use crate::common::playback::stop_walk;
use crate::common::session::Session;
use crate::common::words::WalkReport;
use lab::trial_record::playback::{announce, play_command, upload_table};

/// Play a gait from a slot (ramping from the present posture to its first slice first).
///
/// Ctrl-C stops the walk at the end of its step and waits until the robot stands (a second
/// Ctrl-C exits at once; the board still finishes the step).
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot run --slot 1 --steps 10
  dbot run --slot 1 --steps 4 --backward --period 2.0   # period in s
  dbot run --port physics --table walk.dbgt --steps 2   # upload and walk on a fresh robot
  dbot run --slot 0 --steps 2 --then 1 --then 0:back      # forward, slot 1, backward, stop")]
pub struct Args {
    #[command(flatten)]
    pub slot: crate::args::board::GaitSlotArgs,
    /// Whole steps to play; without it the gait plays until `dbot stop` or Ctrl-C (the board
    /// also stops an endless run 10 s after its host falls silent).
    #[arg(long)]
    pub steps: Option<u32>,
    /// Step period, s (default: the planned one). Between 0.1 and 10 times the planned period;
    /// shorter than planned only when every servo still follows the table at that period (checked
    /// on a `virtual:PATH` robot, whose tables the host holds; elsewhere give --allow-infeasible).
    #[arg(long)]
    pub period: Option<f64>,
    /// Walk backward (slices in reverse order on the same footpaths).
    #[arg(long)]
    pub backward: bool,
    /// Step table to put into the slot first, unless the slot holds it already (so the fresh
    /// robot of `--port physics` or `--port virtual` walks it; on a board it is uploaded, with
    /// every check of `dbot upload`).
    #[arg(long)]
    pub table: Option<std::path::PathBuf>,
    /// Return once the board has started instead of following the steps (needs --steps: the
    /// board stops an endless run whose host is gone).
    #[arg(long)]
    pub detach: bool,
    /// Gait to play next without standing still, `SLOT` or `SLOT:back` (repeatable, in order),
    /// each for --steps at --period; the board refuses one that cannot follow, saying why.
    #[arg(long, value_name = "SLOT[:back]", value_parser = parse_then)]
    pub then: Vec<(u8, bool)>,
    /// Move the perturbation platform under a leg, LEG:STEP:MOVE (e.g. RM:3:rise), as
    /// `dbot record --perturb` does (steps from 0, within --steps; the lab's positions). Without
    /// it a platform left set up is cleared.
    #[arg(long, value_name = "LEG:STEP:MOVE")]
    pub perturb: Option<String>,
    /// With --perturb: the platform servo's bus ID (default: the lab's 22 unless the gait's
    /// joints use it, then the first free ID after theirs: 23 for the built-in model's).
    #[arg(long, requires = "perturb")]
    pub platform_id: Option<u8>,
    #[command(flatten)]
    pub board: BoardArgs,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        if !self.detach {
            interrupt::catch()?;
            interrupt::hold();
        }
        // A leg that is not a leg, a step beyond the run: refused before the port opens.
        let perturb = match &self.perturb {
            Some(spec) => Some(
                board::platform::Perturb::parse(
                    spec,
                    self.platform_id
                        .unwrap_or_else(|| board::platform::default_platform_id_for(None)),
                )
                .and_then(|p| p.check_steps(self.steps).map(|()| p))
                .with_context(|| format!("--perturb {spec}"))?,
            ),
            None => None,
        };
        let mut s = self.board.connect()?;
        let slot = self.slot.slot(&s.setup);
        if s.is_virtual() && (self.steps.is_none() || self.detach) {
            bail!(
                "the virtual robot lives only while dbot runs: give --steps K (and no --detach), \
                 or use `dbot record --play` to walk and record in one command"
            );
        }
        if self.detach && self.steps.is_none() {
            bail!(
                "--detach needs --steps K: an endless run needs its host (the board stops it {} s \
                 after the host falls silent, so a killed host never leaves the robot walking)",
                protocol::limits::HOST_TIMEOUT_CYCLES / 100
            );
        }
        let model = crate::common::model_spec::load_model(
            s.setup.model.as_deref().unwrap_or("drosophibot2"),
        )?;
        let overrides = self.slot.feasibility.overrides();
        if let Some(path) = &self.table {
            let bytes = std::fs::read(path)
                .with_context(|| format!("reading the step table {}", path.display()))?;
            // Checked by the rules as `dbot upload --table` checks it (the same override).
            let (line, warning) = upload_table(
                &mut s.board,
                slot,
                path,
                &bytes,
                &model,
                overrides,
                interrupt::requested,
            )?;
            crate::feasibility_args::warn(warning.as_ref());
            if let Some(line) = line {
                println!("{line}");
            }
        }
        let (command, gait) =
            play_command(&mut s.board, slot, self.steps, self.period, self.backward)?;
        // The platform's servo answers (checked by the board) before anything moves.
        match (&perturb, &self.perturb) {
            (Some(p), Some(spec)) => s
                .board
                .set_platform(p.setup)
                .with_context(|| format!("--perturb {spec}"))?,
            _ if s.board.platform()?.is_some() => {
                s.board.clear_platform().context("clearing the platform")?
            }
            _ => {}
        }
        // Faster than planned: the table's speeds at that period against the servos (the
        // library's rule); the host holds the table of a `virtual:PATH` robot in its image.
        let known = board::rules::period::table_of_port(s.board.port(), slot)?;
        let checked = board::rules::period::check_play(
            &mut s.board,
            command,
            known.as_deref(),
            &model,
            overrides,
        )?;
        crate::feasibility_args::warn(checked.warning());
        // Every queued gait meets the same rule at its own period, before anything moves.
        let mut queued = Vec::with_capacity(self.then.len());
        for &(next, back) in &self.then {
            let (c, _) = play_command(&mut s.board, next, self.steps, self.period, back)?;
            let known = board::rules::period::table_of_port(s.board.port(), next)?;
            let q = board::rules::period::check_queue(
                &mut s.board,
                protocol::QueueCommand(c),
                known.as_deref(),
                &model,
                overrides,
            )
            .with_context(|| format!("--then {next}"))?;
            crate::feasibility_args::warn(q.warning());
            queued.push((next, q));
        }
        println!("{}", announce(slot, &gait, &command));
        if interrupt::requested() {
            bail!("interrupted before the walk started: nothing was played");
        }
        let before = (s.board.now().as_secs_f64(), s.board.status()?.counters);
        s.board
            .play(&checked)
            .with_context(|| format!("playing slot {slot}"))?;
        for (next, q) in &queued {
            s.board
                .queue_gait(q)
                .with_context(|| format!("queueing slot {next} after the gait before it"))?;
        }
        if self.detach {
            println!("slot {slot}: playing");
            return s.close();
        }
        let total = self.steps.map(|k| k * (1 + self.then.len() as u32));
        let steps = follow(&mut s, total)?;
        println!("{}", report(&mut s, before, steps)?.line());
        s.close()
    }
}

/// `--then 3` or `--then 3:back`.
fn parse_then(v: &str) -> Result<(u8, bool), String> {
    let (slot, back) = match v.split_once(':') {
        Some((slot, "back")) => (slot, true),
        Some((_, other)) => return Err(format!("`{other}` after the slot: only `:back` is known")),
        None => (v, false),
    };
    let slot = slot
        .parse()
        .map_err(|_| format!("`{slot}` is not a slot number"))?;
    Ok((slot, back))
}

/// What the walk did: steps, board time and the counters' growth since `before` (board time, s,
/// and counters read just before the play command).
fn report(
    s: &mut Session,
    before: (f64, protocol::Counters),
    steps: u32,
) -> anyhow::Result<WalkReport> {
    let (t0, c0) = before;
    let c = s.board.status()?.counters;
    Ok(WalkReport {
        steps,
        seconds: s.board.now().as_secs_f64() - t0,
        overruns: c.missed_deadlines.wrapping_sub(c0.missed_deadlines),
        bus_errors: (c.bus_timeouts.wrapping_sub(c0.bus_timeouts))
            .wrapping_add(c.crc_errors.wrapping_sub(c0.crc_errors)),
    })
}

/// Follows playback until the robot stands again (or a fault), with a progress bar over the steps;
/// returns the steps completed. On Ctrl-C: asks the board to stop at the end of the step, follows
/// it until it stands and fails with a message saying so.
pub fn follow(s: &mut Session, steps: Option<u32>) -> anyhow::Result<u32> {
    let bar = match steps {
        Some(k) => ProgressBar::new(u64::from(k)).with_style(
            ProgressStyle::with_template("walking {bar:40} step {pos}/{len} {msg}")
                .expect("template is valid"),
        ),
        None => ProgressBar::new_spinner(),
    };
    let mut started = false;
    let mut walked = 0;
    // The gait playing (slot, direction): a change is a queued gait taking over (`--then`).
    let mut playing: Option<(u8, protocol::Direction)> = None;
    // After Ctrl-C: what the stop found (walking: it finishes the step; ramping: it holds where
    // the ramp got to).
    let mut stopped: Option<board::record::Stopped> = None;
    let state = loop {
        if interrupt::requested() && stopped.is_none() {
            bar.println("interrupted: stopping the walk (Ctrl-C again to exit at once)");
            let how = stop_walk(&mut s.board);
            interrupt::release();
            stopped = Some(how?);
        }
        s.board.wait(Duration::from_millis(100))?;
        s.board.discard_telemetry();
        let st = s.board.status()?;
        if let Some(p) = st.playback {
            bar.set_position(u64::from(p.step));
            walked = walked.max(p.step);
            let now = (p.slot, p.direction);
            if playing.is_some_and(|was| was != now) {
                // Printed beside the bar (a hidden bar's println prints nothing).
                bar.suspend(|| {
                    println!(
                        "step {}: slot {} {} follows without a stop",
                        p.step,
                        p.slot,
                        p.direction.name()
                    )
                });
            }
            playing = Some(now);
        }
        bar.set_message(st.state.name());
        match st.state {
            RunState::Ramping | RunState::Walking | RunState::Stopping => started = true,
            RunState::Standing | RunState::Idle if started || stopped.is_some() => break st,
            RunState::Fault => {
                bar.abandon();
                let fault = st
                    .fault
                    .map_or("no fault recorded".to_owned(), |f| f.to_string());
                bail!(
                    "the board stopped with a fault after {walked} step(s): {fault} (see `dbot status`)"
                );
            }
            _ => {}
        }
    };
    bar.finish_and_clear();
    let t = s.board.now().as_secs_f64();
    if let Some(how) = stopped {
        let step = match how {
            board::record::Stopped::AtEndOfStep => state
                .playback
                .map_or(String::new(), |p| format!(" after step {}", p.step)),
            board::record::Stopped::RampHeld
            | board::record::Stopped::StreamingEnded
            | board::record::Stopped::NotWalking => String::new(),
        };
        let what = format!("{}{step}", how.describe());
        bail!(
            "interrupted: {what}; the robot is {} (board clock {t:.2} s)",
            state.state.name()
        );
    }
    // The board stands again only at the end of a step, and a counted walk ends exactly after its
    // last step (firmware `controller`), which the 100 ms polls above may not have caught.
    Ok(match steps {
        Some(k) => k,
        None => walked,
    })
}

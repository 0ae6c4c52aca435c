//! `dbot run`: plays a stored gait, following its steps with a progress bar until the robot stands.
//! Ctrl-C while following stops the walk at the end of the step, waits until the robot stands and
//! exits non-zero; it never leaves the robot walking.

use std::time::Duration;

use anyhow::{Context, bail};
use indicatif::{ProgressBar, ProgressStyle};
use protocol::RunState;

use crate::args::board::BoardArgs;
use crate::common::interrupt;
use crate::common::playback::{play_command, stop_walk};
use crate::common::session::Session;

/// Play a gait from a slot (ramping from the present posture to its first slice first).
///
/// Ctrl-C stops the walk at the end of its step and waits until the robot stands (a second
/// Ctrl-C exits at once; the board still finishes the step).
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Gait slot (default: the setup file's slot, else 0).
    #[arg(long)]
    pub slot: Option<u8>,
    /// Whole steps to play; without it the gait plays until `dbot stop`.
    #[arg(long)]
    pub steps: Option<u32>,
    /// Step period, s (default: the planned one). Between 0.1 and 10 times the planned period.
    #[arg(long)]
    pub period: Option<f64>,
    /// Walk backward (slices in reverse order on the same footpaths).
    #[arg(long)]
    pub backward: bool,
    /// Return once the board has started instead of following the steps.
    #[arg(long)]
    pub detach: bool,
    #[command(flatten)]
    pub board: BoardArgs,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        if !self.detach {
            interrupt::catch()?;
            interrupt::hold();
        }
        let mut s = self.board.connect()?;
        let slot = self.slot.or(s.setup.slot).unwrap_or(0);
        if s.is_virtual() && (self.steps.is_none() || self.detach) {
            bail!(
                "the virtual robot lives only while dbot runs: give --steps K (and no --detach), \
                 or use `dbot record --play` to walk and record in one command"
            );
        }
        let command = play_command(&mut s, slot, self.steps, self.period, self.backward)?;
        if interrupt::requested() {
            bail!("interrupted before the walk started: nothing was played");
        }
        s.board
            .play(command)
            .with_context(|| format!("playing slot {slot}"))?;
        if self.detach {
            println!("slot {slot}: playing");
            return s.close();
        }
        follow(&mut s, self.steps)?;
        s.close()
    }
}

/// Follows playback until the robot stands again (or a fault), with a progress bar over the steps.
/// On Ctrl-C: asks the board to stop at the end of the step, follows it until it stands and fails
/// with a message saying so.
pub fn follow(s: &mut Session, steps: Option<u32>) -> anyhow::Result<()> {
    let bar = match steps {
        Some(k) => ProgressBar::new(u64::from(k)).with_style(
            ProgressStyle::with_template("walking {bar:40} step {pos}/{len} {msg}")
                .expect("template is valid"),
        ),
        None => ProgressBar::new_spinner(),
    };
    let mut started = false;
    // After Ctrl-C: the board's state right after it was asked to stop (Stopping: it finishes
    // the step; Standing: it was still ramping to the first slice and holds where it got to).
    let mut stopped_in: Option<RunState> = None;
    let state = loop {
        if interrupt::requested() && stopped_in.is_none() {
            bar.println(
                "interrupted: stopping at the end of the step (Ctrl-C again to exit at once)",
            );
            stop_walk(&mut s.board)?;
            interrupt::release();
            stopped_in = Some(s.board.status()?.state);
        }
        s.board.wait(Duration::from_millis(100))?;
        s.board.discard_telemetry();
        let st = s.board.status()?;
        if let Some(p) = st.playback {
            bar.set_position(u64::from(p.step));
        }
        bar.set_message(format!("{:?}", st.state));
        match st.state {
            RunState::Ramping | RunState::Walking | RunState::Stopping => started = true,
            RunState::Standing | RunState::Idle if started || stopped_in.is_some() => break st,
            RunState::Fault => {
                bar.abandon();
                bail!("the board stopped with a fault: {:?}", st.fault);
            }
            _ => {}
        }
    };
    bar.finish_and_clear();
    let t = s.board.now().as_secs_f64();
    if let Some(was) = stopped_in {
        // A ramp has no step to finish: the board holds where the ramp got to.
        let what = if matches!(was, RunState::Standing | RunState::Idle) {
            "the ramp to the gait's first slice was stopped where it got to (no step walked)"
                .to_owned()
        } else {
            let step = state
                .playback
                .map_or(String::new(), |p| format!(" after step {}", p.step));
            format!("the walk was stopped at the end of its step{step}")
        };
        bail!(
            "interrupted: {what}; the robot is {:?} (board clock {t:.2} s)",
            state.state
        );
    }
    println!("done: the robot stands (board clock {t:.2} s)");
    Ok(())
}

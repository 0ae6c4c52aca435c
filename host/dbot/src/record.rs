//! `dbot record`: records the board's telemetry as a trial (`board::trial`): a new folder in
//! `--out` per recording, named by its start time, holding the tidy CSV (written as it arrives),
//! the plots of measured against modelled torque (paper fig. 5) and commanded against present
//! angles, a README and trial.json, and a line in `TRIAL INDEX.txt` beside the folders.
//!
//! The trial is recorded into a hidden `.partial-` folder and published when the recording ends:
//! as asked under its start time, after Ctrl-C as `... interrupted`, after a failed link as
//! `... failed`; a recording without a single row is removed. No recording ever replaces another.
//! Ctrl-C stops the walk (whoever started it: `board::record::stop_walk`, the one stop path),
//! records until the robot stands, keeps the trial and exits non-zero.
//!
//! With `--strain PORT` the lab's strain board is recorded beside the servos
//! (`board::strain::StrainBeside`): calibrated before the robot moves, its `strain.csv` put on
//! the telemetry's time base at the end; a strain board that fails mid-recording costs only its
//! own later rows, the servo recording goes on and the trial is kept.
//!
//! The recording is the lab's (`lab::trial_record`, also `Board.record_trial` in Python): this
//! file turns the flags into a `TrialRequest` and gives it Ctrl-C, a spinner and the terminal.

use std::path::PathBuf;

use anyhow::Context;
use indicatif::{ProgressBar, ProgressStyle};
use lab::trial_record::{TrialHooks, TrialPlay, TrialRequest, TrialTable, record_trial};

use crate::args::board::BoardArgs;
use crate::common::interrupt;

/// Record a trial: telemetry, plots, README and trial.json in a new folder of OUT.
///
/// Each recording is a new trial folder in OUT named by its start time (UTC,
/// `YYYY-MM-DD HH_MM_SS`), listed in OUT/TRIAL INDEX.txt. Ctrl-C stops the walk at the end of
/// its step, records until the robot stands and keeps the trial as `... interrupted`.
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot record --out trials --table walk.dbgt --play 1 --steps 10 --notes first-try
  dbot record --out trials --port physics --table walk.dbgt --play 0 --steps 2   # uploads, walks, records
  dbot record --out trials --table walk.dbgt --seconds 20   # whatever the board is doing
  dbot record --out trials --table walk.dbgt --play 1 --steps 10 --strain /dev/ttyACM1   # with strain
  dbot record --out trials --table walk.dbgt --play 1 --steps 6 --perturb RM:3:rise
  dbot record --out trials --port physics:flat+platform:RM --table walk.dbgt --play 0 --steps 6 --perturb RM:3:rise")]
pub struct Args {
    /// Folder of trials: the trial is a new folder in it, listed in its TRIAL INDEX.txt.
    #[arg(long)]
    pub out: PathBuf,
    /// Name of the trial's folder (default: its start time, UTC); one that exists is refused.
    #[arg(long)]
    pub trial: Option<String>,
    /// Free-text notes, kept in the trial's README, trial.json and the index.
    #[arg(long, default_value = "")]
    pub notes: String,
    /// The ground walked on: floor, sandpaper, wire-mesh or anti-slip-mat (kept in the trial).
    /// A physics port's scene names its own (`--port physics:flat+floor`; sandpaper without);
    /// this, if given, must agree with it.
    #[arg(long)]
    pub substrate: Option<String>,
    /// Seconds to record, board clock (default: until the gait started with --play ends, else 10).
    #[arg(long)]
    pub seconds: Option<f64>,
    /// Step table of the gait: its joint map turns load registers into torques and gives the
    /// modelled torque (without it only raw registers are recorded). With --play it is uploaded
    /// into that slot first unless the slot holds it already (so the fresh robot of `--port
    /// physics` or `--port virtual` walks it).
    #[arg(long)]
    pub table: Option<PathBuf>,
    /// The plan directory the step table was built from, for the trial's metadata (default: the
    /// table's folder when it holds a plan.json).
    #[arg(long, requires = "table")]
    pub plan: Option<PathBuf>,
    /// Start this gait slot first and record it (the way to record on the virtual robot).
    #[arg(long)]
    pub play: Option<u8>,
    /// With --play: whole steps to play.
    #[arg(long, requires = "play")]
    pub steps: Option<u32>,
    /// With --play: walk backward.
    #[arg(long, requires = "play")]
    pub backward: bool,
    /// With --play: step period, s (default: the planned one).
    #[arg(long, requires = "play")]
    pub period: Option<f64>,
    /// Record the lab's strain board on this port beside the servos (a serial path, or `virtual`
    /// for a board in this process: fed by the body's simulated gauges on `--port physics`, at
    /// zero strain otherwise); it calibrates before the robot moves.
    #[arg(long, value_name = "PORT")]
    pub strain: Option<String>,
    /// With --play: move the perturbation platform under a leg, LEG:STEP:MOVE (e.g. RM:3:rise):
    /// at the first bus cycle of step STEP (counted from 0, within --steps) the platform servo
    /// goes to `rise` (2330 ticks) or `fall` (1570), two cycles later back to `rest` (2020), the
    /// lab's positions; kept in the trial. Without it a platform left set up is cleared.
    #[arg(long, requires = "play", value_name = "LEG:STEP:MOVE")]
    pub perturb: Option<String>,
    /// With --perturb: the platform servo's bus ID (default: the lab's 22 unless the gait's
    /// joints use it, then the first free ID after theirs: 23 for the built-in model's).
    #[arg(long, requires = "perturb")]
    pub platform_id: Option<u8>,
    /// Telemetry every this many bus cycles (1 to 65535, and at most what the recorder's 2 s
    /// silence limit allows at the bus's rate: 199 at 100 Hz).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u16).range(1..))]
    pub every: u16,
    #[command(flatten)]
    pub board: BoardArgs,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        let setup = self.board.setup()?;
        let spec = setup.model.as_deref().unwrap_or("drosophibot2");
        let request = self.request(crate::common::model_spec::load_model(spec)?)?;
        // Everything that needs no board is refused before any port is opened.
        request.check(self.board.port.as_deref())?;
        interrupt::catch()?;
        // Ctrl-C stops a walk (even one another command started) before a second one may exit.
        interrupt::hold();
        let mut s = self.board.connect()?;
        let mut hooks = Terminal {
            bar: ProgressBar::new_spinner().with_style(
                ProgressStyle::with_template("recording {spinner} {msg}")
                    .expect("template is valid"),
            ),
        };
        let summary = record_trial(&mut s.board, &request, &mut hooks);
        hooks.bar.finish_and_clear();
        println!("{}", summary?);
        s.close()
    }

    /// The flags as the lab's request (the table read, the command line as typed).
    fn request(&self, model: planner::model::Model) -> anyhow::Result<TrialRequest> {
        let table = match &self.table {
            Some(p) => Some(TrialTable {
                path: p.clone(),
                bytes: std::fs::read(p).with_context(|| format!("reading {}", p.display()))?,
            }),
            None => None,
        };
        Ok(TrialRequest {
            out: self.out.clone(),
            trial: self.trial.clone(),
            notes: self.notes.clone(),
            substrate: self.substrate.clone(),
            seconds: self.seconds,
            table,
            plan: self.plan.clone(),
            play: self.play.map(|slot| TrialPlay {
                slot,
                steps: self.steps,
                backward: self.backward,
                period: self.period,
            }),
            strain: self.strain.clone(),
            perturb: self.perturb.clone(),
            platform_id: self.platform_id,
            every: self.every,
            command_line: std::env::args().collect(),
            model,
        })
    }
}

/// The terminal's side of a recording: Ctrl-C, a spinner of board time, the lines printed.
struct Terminal {
    bar: ProgressBar,
}

impl TrialHooks for Terminal {
    fn should_stop(&mut self) -> bool {
        interrupt::requested()
    }

    fn progress(&mut self, t: f64) {
        // Refreshed every tenth of a second of board time.
        if ((t * 100.0).round() as u64).is_multiple_of(10) {
            self.bar.set_message(format!("{t:.1} s of board time"));
            self.bar.tick();
        }
    }

    fn say(&mut self, line: &str) {
        // Shown whether or not the spinner is drawn (it is hidden off a terminal).
        self.bar.suspend(|| println!("{line}"));
    }

    fn stopping(&mut self) {
        self.say(&format!(
            "{} (Ctrl-C again to exit at once)",
            lab::trial_record::STOPPING
        ));
    }

    fn stop_asked(&mut self) {
        interrupt::release();
    }
}

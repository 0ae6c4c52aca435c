//! `dbot record`: records the board's telemetry as a trial (`board::trial`): a new folder in
//! `--out` per recording, named by its start time, holding the tidy CSV (written as it arrives),
//! the plots of measured against modelled torque (paper fig. 5) and commanded against present
//! angles, a README and trial.json, and a line in `TRIAL INDEX.txt` beside the folders.
//!
//! The trial is recorded into a hidden `.partial-` folder and published when the recording ends:
//! as asked under its start time, after Ctrl-C as `... interrupted`, after a failed link as
//! `... failed`, after a fault that stopped the robot as `... faulted` (the fault, its joint and
//! cycle in trial.json and the README; the command exits non-zero naming them); a recording
//! without a single row is removed. No recording ever replaces another.
//! Ctrl-C stops the walk (whoever started it: `board::record::stop_walk`, the one stop path),
//! records until the robot stands, keeps the trial and exits non-zero.
//!
//! With `--strain PORT` the lab's strain board is recorded beside the servos
//! (`board::strain::StrainBeside`): calibrated before the robot moves, its `strain.csv` put on
//! the telemetry's time base at the end; a strain board that fails mid-recording costs only its
//! own later rows, the servo recording goes on and the trial is kept.
//!
//! The recording is the lab's (`lab::trial_record`, also `Board.record_trial` in Python), and so
//! are its flags (`lab::trial_record::TrialArgs`, also Python's keyword arguments): this file
//! gives the recording Ctrl-C, a spinner and the terminal.

use indicatif::{ProgressBar, ProgressStyle};
use lab::trial_record::{TrialArgs, TrialHooks, record_trial};

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
    #[command(flatten)]
    pub trial: TrialArgs,
    #[command(flatten)]
    pub board: BoardArgs,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        let setup = self.board.setup()?;
        let spec = setup.model.as_deref().unwrap_or("drosophibot2");
        let model = crate::common::model_spec::load_model(spec)?;
        let request = self.trial.request(std::env::args().collect(), model)?;
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

    fn warn(&mut self, what: &board::rules::Overridden) {
        // On stderr, as `dbot run --allow-infeasible` warns.
        self.bar
            .suspend(|| crate::feasibility_args::warn(Some(what)));
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

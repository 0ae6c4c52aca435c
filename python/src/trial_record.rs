//! `Board.record_trial(out, ...)`: a trial folder written as `dbot record` writes it, by the same
//! library call (`lab::trial_record::record_trial`): the same refusals in the same words, the same
//! folder, README, trial.json and plots. Ctrl-C (a pending Python signal) stops the walk exactly
//! as it does in the CLI; the trial is kept and `KeyboardInterrupt` is raised naming it.

use std::path::PathBuf;

use lab::trial_record::{TrialArgs, TrialHooks, record_trial};
use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;

use crate::errors::{board_error, value_error};

/// The Python call, as the trial's command line: `python: Board.record_trial(...)` with the
/// arguments given.
fn call_line(args: &TrialArgs) -> Vec<String> {
    let mut line = vec![format!("{:?}", args.out.display().to_string())];
    let mut kw = |name: &str, value: Option<String>| {
        if let Some(v) = value {
            line.push(format!("{name}={v}"));
        }
    };
    let text = |s: &Option<String>| s.as_ref().map(|s| format!("{s:?}"));
    let path = |p: &Option<PathBuf>| p.as_ref().map(|p| format!("{:?}", p.display().to_string()));
    kw("table", path(&args.table));
    kw("plan", path(&args.plan));
    kw("play", args.play.map(|v| v.to_string()));
    kw("steps", args.steps.map(|v| v.to_string()));
    kw("backward", args.backward.then(|| "True".to_owned()));
    kw("period", args.period.map(|v| v.to_string()));
    kw(
        "allow_infeasible",
        args.allow_infeasible.then(|| "True".to_owned()),
    );
    kw("seconds", args.seconds.map(|v| v.to_string()));
    kw(
        "notes",
        (!args.notes.is_empty()).then(|| format!("{:?}", args.notes)),
    );
    kw("trial", text(&args.trial));
    kw("substrate", text(&args.substrate));
    kw("strain", text(&args.strain));
    kw("perturb", text(&args.perturb));
    kw("platform_id", args.platform_id.map(|v| v.to_string()));
    kw("every", (args.every != 1).then(|| args.every.to_string()));
    vec![
        "python:".to_owned(),
        format!("Board.record_trial({})", line.join(", ")),
    ]
}

/// Python's side of a recording: pending signals (Ctrl-C) stop the walk; lines are printed.
struct PythonDoor<'py> {
    py: Python<'py>,
    /// The signal's exception, raised once the trial is kept.
    signal: Option<PyErr>,
    /// The override's warning, raised by a filter that makes warnings errors: raised instead of
    /// the refusal it caused (the walk is not started).
    warning_raised: Option<PyErr>,
}

impl TrialHooks for PythonDoor<'_> {
    fn should_stop(&mut self) -> bool {
        if self.warning_raised.is_some() {
            return true;
        }
        if self.signal.is_none()
            && let Err(e) = self.py.check_signals()
        {
            self.signal = Some(e);
        }
        self.signal.is_some()
    }

    fn say(&mut self, line: &str) {
        println!("{line}");
    }

    fn warn(&mut self, what: &::board::rules::Overridden) {
        // A UserWarning, as `Board.play(allow_infeasible=True)` warns. A filter that turns it
        // into an error (`-W error`) stops the walk before it starts, as a Ctrl-C would.
        if let Err(e) = crate::errors::warn_overridden(self.py, Some(what)) {
            self.warning_raised = Some(e);
        }
    }
}

/// Records the trial `args` asks for on `link`, naming joints from `model`; returns the published
/// folder. ValueError with the CLI's words for a refusal, `dbot.BoardError` for a failed link,
/// KeyboardInterrupt (naming the kept trial) after Ctrl-C, `dbot.TrialFaulted` (naming the fault
/// and the kept trial) when the board stopped the robot on a fault.
pub fn record(
    py: Python<'_>,
    link: &mut physics::Robot,
    args: &TrialArgs,
    model: planner::model::Model,
    held_table: Option<Vec<u8>>,
) -> PyResult<PathBuf> {
    let mut request = args
        .request(call_line(args), model)
        .map_err(|e| value_error(e.chain_text()))?;
    request.held_table = held_table;
    let mut door = PythonDoor {
        py,
        signal: None,
        warning_raised: None,
    };
    let result = record_trial(link, &request, &mut door);
    if let (Err(_), Some(e)) = (&result, door.warning_raised) {
        return Err(e);
    }
    match result {
        Ok(summary) => {
            println!("{summary}");
            Ok(summary.path)
        }
        Err(e @ lab::LabError::Interrupted(_)) => Err(PyKeyboardInterrupt::new_err(e.chain_text())),
        Err(e @ lab::LabError::Faulted(_)) => {
            Err(crate::errors::TrialFaulted::new_err(e.chain_text()))
        }
        Err(e) if is_link_failure(&e) => Err(board_error(e.chain_text())),
        Err(e) => Err(value_error(e.chain_text())),
    }
}

/// Whether the board's link failed somewhere in `e`'s chain.
fn is_link_failure(e: &lab::LabError) -> bool {
    let mut cur: Option<&(dyn std::error::Error + 'static)> = Some(e);
    while let Some(err) = cur {
        if err.is::<::board::link::LinkError>() {
            return true;
        }
        cur = err.source();
    }
    false
}

//! `Board.record_trial(out, ...)`: a trial folder written as `dbot record` writes it, by the same
//! library call (`lab::trial_record::record_trial`): the same refusals in the same words, the same
//! folder, README, trial.json and plots. Ctrl-C (a pending Python signal) stops the walk exactly
//! as it does in the CLI; the trial is kept and `KeyboardInterrupt` is raised naming it.

use std::path::PathBuf;

use lab::trial_record::{TrialHooks, TrialPlay, TrialRequest, TrialTable, record_trial};
use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;

use crate::errors::{board_error, value_error};

/// The keyword arguments of `Board.record_trial`, as `dbot record`'s flags.
#[derive(Debug, Default)]
pub struct TrialArgs {
    pub out: PathBuf,
    pub table: Option<PathBuf>,
    pub plan: Option<PathBuf>,
    pub play: Option<u8>,
    pub steps: Option<u32>,
    pub backward: bool,
    pub period: Option<f64>,
    pub seconds: Option<f64>,
    pub notes: String,
    pub trial: Option<String>,
    pub substrate: Option<String>,
    pub strain: Option<String>,
    pub perturb: Option<String>,
    pub platform_id: Option<u8>,
    pub every: u16,
}

impl TrialArgs {
    /// The Python call, as the trial's command line: `python: Board.record_trial(...)` with the
    /// arguments given.
    fn call_line(&self) -> Vec<String> {
        let mut args = vec![format!("{:?}", self.out.display().to_string())];
        let mut kw = |name: &str, value: Option<String>| {
            if let Some(v) = value {
                args.push(format!("{name}={v}"));
            }
        };
        let text = |s: &Option<String>| s.as_ref().map(|s| format!("{s:?}"));
        let path =
            |p: &Option<PathBuf>| p.as_ref().map(|p| format!("{:?}", p.display().to_string()));
        kw("table", path(&self.table));
        kw("plan", path(&self.plan));
        kw("play", self.play.map(|v| v.to_string()));
        kw("steps", self.steps.map(|v| v.to_string()));
        kw("backward", self.backward.then(|| "True".to_owned()));
        kw("period", self.period.map(|v| v.to_string()));
        kw("seconds", self.seconds.map(|v| v.to_string()));
        kw(
            "notes",
            (!self.notes.is_empty()).then(|| format!("{:?}", self.notes)),
        );
        kw("trial", text(&self.trial));
        kw("substrate", text(&self.substrate));
        kw("strain", text(&self.strain));
        kw("perturb", text(&self.perturb));
        kw("platform_id", self.platform_id.map(|v| v.to_string()));
        kw("every", (self.every != 1).then(|| self.every.to_string()));
        vec![
            "python:".to_owned(),
            format!("Board.record_trial({})", args.join(", ")),
        ]
    }

    /// The lab's request (the table read from its file).
    fn request(&self, model: planner::model::Model) -> PyResult<TrialRequest> {
        let table = match &self.table {
            Some(p) => Some(TrialTable {
                path: p.clone(),
                bytes: std::fs::read(p)
                    .map_err(|e| value_error(format!("reading {}: {e}", p.display())))?,
            }),
            None => None,
        };
        if self.play.is_none() {
            let needs_play = [
                ("steps", self.steps.is_some()),
                ("backward", self.backward),
                ("period", self.period.is_some()),
                ("perturb", self.perturb.is_some()),
            ];
            if let Some((name, _)) = needs_play.iter().find(|(_, given)| *given) {
                return Err(value_error(format!("{name} needs play = SLOT")));
            }
        }
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
            command_line: self.call_line(),
            model,
        })
    }
}

/// Python's side of a recording: pending signals (Ctrl-C) stop the walk; lines are printed.
struct PythonDoor<'py> {
    py: Python<'py>,
    /// The signal's exception, raised once the trial is kept.
    signal: Option<PyErr>,
}

impl TrialHooks for PythonDoor<'_> {
    fn should_stop(&mut self) -> bool {
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
}

/// Records the trial `args` asks for on `link`, naming joints from `model`; returns the published
/// folder. ValueError with the CLI's words for a refusal, `dbot.BoardError` for a failed link,
/// KeyboardInterrupt (naming the kept trial) after Ctrl-C.
pub fn record(
    py: Python<'_>,
    link: &mut physics::Robot,
    args: &TrialArgs,
    model: planner::model::Model,
) -> PyResult<PathBuf> {
    let request = args.request(model)?;
    let mut door = PythonDoor { py, signal: None };
    match record_trial(link, &request, &mut door) {
        Ok(summary) => {
            println!("{summary}");
            Ok(summary.path)
        }
        Err(e @ lab::LabError::Interrupted(_)) => Err(PyKeyboardInterrupt::new_err(e.chain_text())),
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

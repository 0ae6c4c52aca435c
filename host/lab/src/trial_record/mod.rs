//! Recording a trial (`board::trial`): the one call behind `dbot record` and
//! `Board.record_trial`. A new folder in the request's `out` per recording, named by its start
//! time, holding the tidy CSV (written as it arrives), the plots of measured against modelled
//! torque (paper fig. 5) and commanded against present angles, a README and trial.json, and a
//! line in `TRIAL INDEX.txt` beside the folders.
//!
//! Every refusal ([`TrialRequest::check`]) comes before anything moves. The trial is recorded
//! into a hidden `.partial-` folder and published when the recording ends: as asked under its
//! start time, after the caller's stop ([`TrialHooks::should_stop`], Ctrl-C in the CLI) as
//! `... interrupted`, after a failed link as `... failed`, after a fault that stopped the robot
//! as `... faulted` (failing with [`LabError::Faulted`] naming the fault, its joint and cycle); a
//! recording without a single row is removed. No recording ever replaces another. A stop asks the board to end the walk
//! (`board::record::stop_walk`, the one stop path), records until the robot stands, keeps the
//! trial and fails with [`LabError::Interrupted`] naming it.
//!
//! With a strain port the lab's strain board is recorded beside the servos
//! (`board::strain::StrainBeside`): calibrated before the robot moves, its `strain.csv` put on
//! the telemetry's time base at the end; a strain board that fails mid-recording costs only its
//! own later rows, the servo recording goes on and the trial is kept.
//!
//! - [`args`]: the trial's options as the user gives them (`dbot record`'s flags, Python's
//!   keyword arguments), turned into a [`TrialRequest`].
//! - [`playback`]: the table put into a slot first, the play command and its announcement
//!   (also `dbot run`'s).
//! - [`joints`]: the recorded joints named from the model.

pub mod args;
mod capture;
mod check;
pub mod joints;
pub mod playback;
mod start;
mod summary;

use std::path::PathBuf;

use planner::model::Model;

pub use args::TrialArgs;
pub use check::Checked;
pub use summary::TrialSummary;

use crate::error::{LabError, Result};

/// A step table given for the trial: where it came from and its bytes.
#[derive(Debug, Clone)]
pub struct TrialTable {
    pub path: PathBuf,
    pub bytes: Vec<u8>,
}

/// The gait the trial starts itself (the way to record on the virtual robot).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrialPlay {
    pub slot: u8,
    /// Whole steps to play; `None`: until stopped.
    pub steps: Option<u32>,
    pub backward: bool,
    /// Step period, s; `None`: the planned one. Shorter than planned only where the servos can
    /// follow the table (`board::rules::period`, the rule of `dbot run --period`).
    pub period: Option<f64>,
    /// Play at `period` even when a servo cannot follow the table there (warned).
    pub allow_infeasible: bool,
}

/// Everything a trial is recorded from. Its errors name a field by the word both doors use
/// (`perturb RM:2:rise: ...`, `seconds -1: ...`: `dbot record --perturb`, Python's
/// `record_trial(perturb=...)`), and what to give in both spellings (`give --play SLOT (Python:
/// play=SLOT)`), the same from every door.
#[derive(Debug, Clone)]
pub struct TrialRequest {
    /// Folder of trials: the trial is a new folder in it, listed in its TRIAL INDEX.txt.
    pub out: PathBuf,
    /// Name of the trial's folder (default: its start time, UTC); one that exists is refused.
    pub trial: Option<String>,
    /// Free-text notes, kept in the trial's README, trial.json and the index.
    pub notes: String,
    /// The ground walked on (`floor`, `sandpaper`, ...); a physics port's scene must agree.
    pub substrate: Option<String>,
    /// Seconds to record, board clock (default: until the gait played ends, else 10).
    pub seconds: Option<f64>,
    /// The gait's step table: its joint map turns load registers into torques and gives the
    /// modelled torque; with `play` it is uploaded into that slot first unless the slot holds it.
    pub table: Option<TrialTable>,
    /// The plan directory the table was built from (default: the table's folder when it holds
    /// a plan.json).
    pub plan: Option<PathBuf>,
    pub play: Option<TrialPlay>,
    /// The lab's strain board on this port, recorded beside the servos.
    pub strain: Option<String>,
    /// With `play`: the perturbation platform's move, `LEG:STEP:MOVE` (e.g. `RM:3:rise`).
    pub perturb: Option<String>,
    /// The platform servo's bus ID (`None`: [`platform_id`]'s default).
    pub platform_id: Option<u8>,
    /// Telemetry every this many bus cycles.
    pub every: u16,
    /// The step table the door knows to be in the played slot when `table` is not given (Python:
    /// one this `Board` uploaded there): what a period shorter than planned is checked against.
    /// Without either, a `virtual:PATH` robot's image is read; a board's table is unknown.
    pub held_table: Option<Vec<u8>>,
    /// The command line kept in the trial (program name first).
    pub command_line: Vec<String>,
    /// The model whose joint names the recording's joints get.
    pub model: Model,
}

impl TrialRequest {
    /// A trial into the folder `out` that plays `steps` steps forward of the gait in `slot` at
    /// its planned period (`None`: until stopped), telemetry every cycle, joints named by
    /// `model`; everything else at its default (no table, strain or perturbation). Change fields
    /// with struct update syntax: `TrialRequest { notes, ..TrialRequest::playing(..) }`.
    pub fn playing(out: &std::path::Path, slot: u8, steps: Option<u32>, model: Model) -> Self {
        Self {
            out: out.to_owned(),
            trial: None,
            notes: String::new(),
            substrate: None,
            seconds: None,
            table: None,
            plan: None,
            play: Some(TrialPlay {
                slot,
                steps,
                backward: false,
                period: None,
                allow_infeasible: false,
            }),
            strain: None,
            perturb: None,
            platform_id: None,
            every: 1,
            held_table: None,
            command_line: Vec::new(),
            model,
        }
    }
}

/// The platform servo's bus ID of `request`: the one place its default is chosen.
/// Without one given: the lab's 22 unless the table's joints use it, then the first free ID after
/// theirs (`board::platform::default_platform_id_for`).
pub fn platform_id(request: &TrialRequest) -> u8 {
    request.platform_id.unwrap_or_else(|| {
        board::platform::default_platform_id_for(request.table.as_ref().map(|t| t.bytes.as_slice()))
    })
}

/// The line said when a stop was asked for while the trial records.
pub const STOPPING: &str = "interrupted: stopping the walk";

/// What the door (CLI, Python) does while a trial records.
pub trait TrialHooks {
    /// Whether the user asked to stop (Ctrl-C): the walk is stopped at the end of its step, the
    /// recording goes on until the robot stands, the trial is kept as interrupted.
    fn should_stop(&mut self) -> bool;
    /// The recording reached `board_s` seconds of board time (called for every record).
    fn progress(&mut self, board_s: f64) {
        let _ = board_s;
    }
    /// A line for the user (the upload, the playback's announcement, the strain board's
    /// calibration, the stop).
    fn say(&mut self, line: &str);
    /// What an override let through (`allow_infeasible`), in the library's words: by default
    /// said as `warning: ...`.
    fn warn(&mut self, what: &board::rules::Overridden) {
        self.say(&format!("warning: {what}"));
    }
    /// The walk is about to be stopped (after [`TrialHooks::should_stop`]): by default says
    /// [`STOPPING`].
    fn stopping(&mut self) {
        self.say(STOPPING);
    }
    /// The board was asked to stop the walk (whatever it answered).
    fn stop_asked(&mut self) {}
}

/// Records the trial `request` asks for on `board` and publishes it; returns its summary.
/// Refused before anything moves: everything [`TrialRequest::check`] refuses, a trial folder
/// that exists or cannot be written, the virtual robot without `play`, a telemetry rate the
/// recorder cannot serve, a platform servo that does not answer. If the board vanishes or the
/// caller stops the recording, the rows so far are kept in a trial named so, and the error says
/// so (after a stop, once the robot stands: [`LabError::Interrupted`]).
pub fn record_trial(
    board: &mut physics::Robot,
    request: &TrialRequest,
    hooks: &mut dyn TrialHooks,
) -> Result<TrialSummary> {
    let checked = request.check(Some(board.port()))?;
    let folder = board::trial::TrialFolder::begin(
        &request.out,
        request.trial.as_deref(),
        std::time::SystemTime::now(),
    )
    .map_err(library)?;
    match start::start(board, request, &checked, &folder, hooks) {
        Ok(started) => capture::record(board, folder, started, hooks),
        Err(e) => {
            // Nothing was recorded: no trial.
            folder.discard();
            Err(e)
        }
    }
}

/// A library error as it is.
fn library(e: impl std::error::Error + Send + Sync + 'static) -> LabError {
    LabError::Library(Box::new(e))
}

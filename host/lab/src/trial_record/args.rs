//! The trial's options as a user gives them, one owner for both doors: `dbot record`'s flags
//! (with the `clap` feature this type is the flags, its doc comments their help) and
//! `Board.record_trial`'s keyword arguments (`python/src/trial_record.rs` fills it). Turned into
//! the [`TrialRequest`] the recording runs from by [`TrialArgs::request`], the one place the
//! table is read and the options that only make sense with `play` are refused without it.

use std::path::PathBuf;

use planner::model::Model;

use super::{TrialPlay, TrialRequest, TrialTable};
use crate::error::{Context, Result};

/// What a trial records and how (the flags of `dbot record`, the keyword arguments of
/// `Board.record_trial`).
#[derive(Debug, Clone, Default)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct TrialArgs {
    /// Folder of trials: the trial is a new folder in it, listed in its TRIAL INDEX.txt.
    #[cfg_attr(feature = "clap", arg(long))]
    pub out: PathBuf,
    /// Name of the trial's folder (default: its start time, UTC); one that exists is refused.
    #[cfg_attr(feature = "clap", arg(long))]
    pub trial: Option<String>,
    /// Free-text notes, kept in the trial's README, trial.json and the index.
    #[cfg_attr(feature = "clap", arg(long, default_value = ""))]
    pub notes: String,
    /// The ground walked on: floor, sandpaper, wire-mesh or anti-slip-mat (kept in the trial).
    /// A physics port's scene names its own (`--port physics:flat+floor`; sandpaper without);
    /// this, if given, must agree with it.
    #[cfg_attr(feature = "clap", arg(long))]
    pub substrate: Option<String>,
    /// Seconds to record, board clock (default: until the gait started with --play ends, else 10).
    #[cfg_attr(feature = "clap", arg(long))]
    pub seconds: Option<f64>,
    /// Step table of the gait: its joint map turns load registers into torques and gives the
    /// modelled torque (without it only raw registers are recorded). With --play it is uploaded
    /// into that slot first unless the slot holds it already (so the fresh robot of `--port
    /// physics` or `--port virtual` walks it).
    #[cfg_attr(feature = "clap", arg(long))]
    pub table: Option<PathBuf>,
    /// The plan directory the step table was built from, for the trial's metadata (default: the
    /// table's folder when it holds a plan.json).
    #[cfg_attr(feature = "clap", arg(long, requires = "table"))]
    pub plan: Option<PathBuf>,
    /// Start this gait slot first and record it (the way to record on the virtual robot).
    #[cfg_attr(feature = "clap", arg(long))]
    pub play: Option<u8>,
    /// With --play: whole steps to play.
    #[cfg_attr(feature = "clap", arg(long, requires = "play"))]
    pub steps: Option<u32>,
    /// With --play: walk backward.
    #[cfg_attr(feature = "clap", arg(long, requires = "play"))]
    pub backward: bool,
    /// With --play: step period, s (default: the planned one).
    #[cfg_attr(feature = "clap", arg(long, requires = "play"))]
    pub period: Option<f64>,
    /// With --play: upload the --table file and play it (at a --period shorter than planned too)
    /// even when a servo cannot follow it (as `dbot run --allow-infeasible`); a warning names what
    /// it let through.
    #[cfg_attr(feature = "clap", arg(long, requires = "play"))]
    pub allow_infeasible: bool,
    /// Record the lab's strain board on this port beside the servos (a serial path, or `virtual`
    /// for a board in this process: fed by the body's simulated gauges on `--port physics`, at
    /// zero strain otherwise); it calibrates before the robot moves.
    #[cfg_attr(feature = "clap", arg(long, value_name = "PORT"))]
    pub strain: Option<String>,
    /// With --play: move the perturbation platform under a leg, LEG:STEP:MOVE (e.g. RM:3:rise):
    /// at the first bus cycle of step STEP (counted from 0, within --steps) the platform servo
    /// goes to `rise` (2330 ticks) or `fall` (1570), two cycles later back to `rest` (2020), the
    /// lab's positions; kept in the trial. Without it a platform left set up is cleared.
    #[cfg_attr(
        feature = "clap",
        arg(long, requires = "play", value_name = "LEG:STEP:MOVE")
    )]
    pub perturb: Option<String>,
    /// With --perturb: the platform servo's bus ID (default: the lab's 22 unless the gait's
    /// joints use it, then the first free ID after theirs: 23 for the built-in model's).
    #[cfg_attr(feature = "clap", arg(long, requires = "perturb"))]
    pub platform_id: Option<u8>,
    /// Telemetry every this many bus cycles (1 to 65535, and at most what the recorder's 2 s
    /// silence limit allows at the bus's rate: 199 at 100 Hz).
    #[cfg_attr(
        feature = "clap",
        arg(long, default_value_t = 1, value_parser = clap::value_parser!(u16).range(1..))
    )]
    pub every: u16,
}

impl TrialArgs {
    /// The request the recording runs from: the table read from its file, `command_line` (the
    /// door's own words for the call, program first) and `model` (whose joint names the
    /// recorded joints get) kept in the trial. Refused: `steps`, `backward`, `period`,
    /// `allow_infeasible` or `perturb` without `play`, a table that cannot be read.
    pub fn request(&self, command_line: Vec<String>, model: Model) -> Result<TrialRequest> {
        let table = match &self.table {
            Some(p) => Some(TrialTable {
                path: p.clone(),
                bytes: std::fs::read(p).with_context(|| format!("reading {}", p.display()))?,
            }),
            None => None,
        };
        if self.play.is_none() {
            let needs_play = [
                ("steps", self.steps.is_some()),
                ("backward", self.backward),
                ("period", self.period.is_some()),
                ("allow_infeasible", self.allow_infeasible),
                ("perturb", self.perturb.is_some()),
            ];
            if let Some((name, _)) = needs_play.iter().find(|(_, given)| *given) {
                crate::bail!("{name} needs a slot to play: give --play SLOT (Python: play=SLOT)");
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
                allow_infeasible: self.allow_infeasible,
            }),
            strain: self.strain.clone(),
            perturb: self.perturb.clone(),
            platform_id: self.platform_id,
            every: self.every,
            held_table: None,
            command_line,
            model,
        })
    }
}

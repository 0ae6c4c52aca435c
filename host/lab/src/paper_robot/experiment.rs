//! One of the paper's robot experiments on the physics robot: plan Drosophibot II's tripod at a
//! step period (table 1 with the swing time set so that period = swing / (1 - duty)), solve its
//! inverse dynamics, upload the step table, walk it on a scene while recording, and reduce the
//! recording to per-slice statistics of the torque estimated from each servo's load register
//! beside the planner's torque (the paper's figures 5 to 7 plot the same); and the body's
//! simulated gauges against the plan's predicted strain ([`crate::strain_walk`]).

use std::path::Path;

use board::link::Board;
use board::record::{Ended, joints_of_table, phase_stats};
use physics::PhysicsRobot;
use planner::gait::StepParams;
use planner::model::Leg;
use planner::terrain::Ground;
use protocol::Direction;

use crate::error::{Context, LabError, Result};
use crate::walk::{play_and_record, solve_walk_dynamics};
use crate::walk_fits::Fit;

/// One walk to simulate.
#[derive(Debug, Clone, PartialEq)]
pub struct Experiment {
    /// Name in the CSV and plots, e.g. `forward-2s`.
    pub name: String,
    /// Step period the gait is planned at, s.
    pub period_s: f64,
    pub direction: Direction,
    /// Scene and planner terrain: flat or an incline.
    pub terrain: Ground,
    /// Steps walked; the first is left out of the statistics (it starts from the ramp).
    pub steps: u32,
}

impl Experiment {
    pub fn new(period_s: f64, direction: Direction, terrain: Ground, steps: u32) -> Self {
        let dir = if direction == Direction::Forward {
            "forward"
        } else {
            "backward"
        };
        let ground = match terrain {
            Ground::Flat => String::new(),
            other => format!("-{}", other.to_string().replace(':', "")),
        };
        Self {
            name: format!("{dir}{ground}-{period_s}s"),
            period_s,
            direction,
            terrain,
            steps,
        }
    }
}

/// One joint at one slice of the step, over the recorded steps.
#[derive(Debug, Clone, PartialEq)]
pub struct PhaseRow {
    pub experiment: String,
    pub joint: String,
    pub slice: usize,
    pub slices: usize,
    /// The joint's leg stands at this slice (the plan's stance).
    pub stance: bool,
    /// The planner's torque (the step table's, quantised to 1 mN m), N m.
    pub planned_nm: f64,
    /// Torque estimated from the load register: mean and standard deviation over the steps, N m.
    pub mean_nm: f64,
    pub sd_nm: f64,
    /// Samples (bus cycles) behind the mean.
    pub n: usize,
}

/// The tripod at `period_s` (duty of table 1) on `terrain`.
pub fn params(period_s: f64, terrain: Ground) -> Result<StepParams> {
    let mut p = StepParams::preset("table1", "drosophibot2").context("table1 preset")?;
    p.swing_s = period_s * (1.0 - p.duty);
    p.terrain = terrain;
    Ok(p)
}

/// The step parameters `e` is planned with. Backward is planned as its own gait (the planner
/// walks backward at a negative translation) and played forward, so its torques, bias and stance
/// phases are the backward plan's, not the forward plan's played in reverse.
pub fn plan_params(e: &Experiment) -> Result<StepParams> {
    let mut p = params(e.period_s, e.terrain)?;
    if e.direction == Direction::Backward {
        p.translation_m = -p.translation_m.abs();
    }
    Ok(p)
}

/// Plans, walks and reduces `e`; the recording goes to `dir/telemetry.csv`, or to a scratch file
/// removed afterwards without `dir`. Returns the load rows and, per gauge, the simulated gauges
/// against the predicted strain over the same steps. `stop` returning true ends the walk early,
/// with [`LabError::Interrupted`].
pub fn run(
    e: &Experiment,
    dir: Option<&Path>,
    stop: impl Fn() -> bool,
) -> Result<(Vec<PhaseRow>, Vec<Fit>)> {
    let model = planner::model::builtin("drosophibot2")?;
    let p = plan_params(e)?;
    let plan = planner::plan::plan(&model, &p)
        .with_context(|| format!("{}: planning the step", e.name))?;
    let cycle =
        solve_walk_dynamics(&plan).with_context(|| format!("{}: inverse dynamics", e.name))?;
    let torque = planner::dynamics::output::torque_rows(&cycle);
    let table = planner::plan::table::step_table(&plan, Some(&torque), "paper robot")
        .with_context(|| format!("{}: step table", e.name))?;
    let servo_joints = planner::plan::table::servo_joints(&model);
    let names: Vec<String> = servo_joints
        .iter()
        .map(|&j| model.joints[j].name.clone())
        .collect();
    let legs: Vec<Leg> = servo_joints.iter().map(|&j| model.joints[j].leg).collect();

    let mut body = PhysicsRobot::drosophibot(&e.terrain)
        .with_context(|| format!("{}: the physics robot", e.name))?;
    let gauges = body.gauge_names();
    body.start_log(usize::MAX);
    let mut board = Board::connect(body.into_transport())?;
    let checked = crate::simulated::checked(&table, &e.name)?;
    board.upload(0, &checked, |_, _| {})?;
    let parsed = protocol::GaitTable::parse(&table)?;
    let joints = joints_of_table(&parsed, &names);
    let csv = match dir {
        Some(dir) => {
            std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
            dir.join("telemetry.csv")
        }
        None => std::env::temp_dir().join(format!(
            "dbot-paper-robot-{}-{}.csv",
            std::process::id(),
            e.name
        )),
    };
    // The backward walk plays its own plan (below) forward.
    let (rec, ended) = play_and_record(&mut board, Direction::Forward, e.steps, &csv, joints, stop)
        .with_context(|| format!("{}: recording", e.name))?;
    if dir.is_none() {
        let _ = std::fs::remove_file(&csv);
    }
    if ended == Ended::Interrupted {
        return Err(LabError::Interrupted(format!(
            "interrupted while walking {}",
            e.name
        )));
    }
    let log = board
        .transport_mut()
        .robot_mut()
        .servos_mut()
        .take_log()
        .unwrap_or_default();
    let predicted = crate::strain_walk::predicted(&plan, &cycle)?;
    let strain = crate::strain_walk::strain_fits(&log, &gauges, &predicted, e.steps);
    let first = u32::from(e.steps >= 2);
    let walking: Vec<_> = rec
        .rows()
        .iter()
        .filter(|r| r.step >= first && r.step < e.steps)
        .cloned()
        .collect();
    let slices = plan.slices();
    let mut out = Vec::new();
    for (j, name) in names.iter().enumerate() {
        let leg = plan
            .legs
            .iter()
            .position(|&l| l == legs[j])
            .with_context(|| format!("{}: joint {name} has no leg in the plan", e.name))?;
        for s in phase_stats(&walking, j, slices) {
            let slice = (s.phase * slices as f64).round() as usize;
            out.push(PhaseRow {
                experiment: e.name.clone(),
                joint: name.clone(),
                slice,
                slices,
                stance: plan.stance[slice][leg],
                planned_nm: s.modelled_nm.with_context(|| {
                    format!(
                        "{}: joint {name} slice {slice} has no planned torque",
                        e.name
                    )
                })?,
                mean_nm: s.mean_nm,
                sd_nm: s.sd_nm,
                n: s.n,
            });
        }
    }
    Ok((out, strain))
}

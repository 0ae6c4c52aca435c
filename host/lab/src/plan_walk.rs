//! A walk a researcher runs themselves: a plan directory's step table (built as `dbot table
//! --plan` builds it) uploaded to a fresh physics robot and walked while recording, and the
//! figures `dbot demo` prints for such a walk, computed from what it recorded. Walked the same
//! way on the same plan directory, the figures equal the demo's forward walk's (the physics robot
//! is deterministic).

use std::path::Path;

use board::link::Board;
use board::record::joints_of_table;
use physics::{Figures, PhysicsRobot};
use planner::plan_dir;
use protocol::Direction;

use crate::demo::{WalkHow, walk_recorded};
use crate::error::{Context, LabError, Result};
use crate::walk_body::{Distance, LegTracking, distance, leg_tracking};
use crate::walk_files::Walk;
use crate::walk_fits::{Fit, load_fits};

/// A recorded walk of a plan directory's gait.
#[derive(Debug)]
pub struct PlanWalk {
    pub walk: Walk,
    /// The servo joints' names, in table order.
    pub names: Vec<String>,
    /// Steps played.
    pub steps: u32,
    /// The plan's thorax travel per step, m.
    pub planned_per_step_m: f64,
    /// The foot stroke of the plan, m.
    pub translation_m: f64,
}

/// Walks the gait of the plan directory `plan_dir` for `steps` steps in `direction` on a fresh
/// physics robot on `scene`, recording into `out` (telemetry.csv, torque.png, angles.png).
pub fn walk_plan_dir(
    plan_dir: &Path,
    scene: &planner::terrain::Ground,
    steps: u32,
    direction: Direction,
    out: &Path,
    stop: impl Fn() -> bool,
) -> Result<PlanWalk> {
    if steps == 0 {
        crate::bail!("steps 0: give at least one step");
    }
    let written = plan_dir::read(plan_dir)?;
    let table = written
        .step_table(None)
        .with_context(|| format!("the step table of {}", plan_dir.display()))?;
    let names = written.servo_joint_names();
    let body = PhysicsRobot::drosophibot(scene)?;
    let mut board = Board::connect(body.into_transport())?;
    let checked = crate::simulated::checked(&table, &plan_dir.display().to_string())?;
    board.upload(0, &checked, |_, _| {})?;
    let parsed = protocol::GaitTable::parse(&table)?;
    let joints = joints_of_table(&parsed, &names);
    let how = WalkHow {
        label: match direction {
            Direction::Forward => "forward",
            Direction::Backward => "backward",
        },
        direction,
        bias_on: true,
        steps,
        slices: parsed.slice_count(),
    };
    let walk = walk_recorded(&mut board, &how, out, joints, stop)?.ok_or_else(|| {
        LabError::Interrupted(format!(
            "interrupted while recording into {}",
            out.display()
        ))
    })?;
    let json = &written.json;
    Ok(PlanWalk {
        walk,
        names,
        steps,
        planned_per_step_m: json.thorax_velocity_m_s.x * json.period_s,
        translation_m: json.parameters.translation_m,
    })
}

/// The figures `dbot demo` prints for one walk with a body.
#[derive(Debug, Clone, PartialEq)]
pub struct WalkFigures {
    /// What the body did (distance, heading, height, tilt, slip).
    pub body: Figures,
    pub distance: Distance,
    /// Tracking error per leg (empty with fewer than 2 steps).
    pub tracking: Vec<LegTracking>,
    /// Servo load (ESTIMATE from Present Load) against the planned torque, per joint.
    pub loads: Vec<Fit>,
}

/// The figures of `w` (`None`: the walk had no body).
pub fn walk_figures(w: &PlanWalk) -> Option<WalkFigures> {
    let body = w.walk.figures.clone()?;
    let modelled: Vec<Vec<f64>> = w
        .walk
        .rec
        .joints()
        .iter()
        .map(|m| m.modelled_nm.clone())
        .collect();
    Some(WalkFigures {
        distance: distance(&body, w.planned_per_step_m, w.steps, w.walk.direction),
        tracking: leg_tracking(w.walk.rec.rows(), &w.names),
        loads: load_fits(w.walk.rec.rows(), &w.names, &modelled, w.steps),
        body,
    })
}

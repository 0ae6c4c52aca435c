//! The walk `dbot demo`, `dbot paper-robot` and Python record on a (physics or virtual) robot:
//! the gait in slot 0 played for a number of steps in a direction, its telemetry captured until
//! the robot stands again or the caller asks to stop; and the one choice of inverse dynamics the
//! walks' step tables are built from.

use std::path::Path;

use board::link::{Board, Transport};
use board::record::{Ended, JointMeta, Recorder, Until, capture_while};
use planner::dynamics::{CycleSolution, DynamicsOptions, plan_inputs, solve_cycle};
use planner::plan::Plan;
use protocol::{Direction, PlayCommand, Steps};

use crate::error::{Context, Result};

/// Friction coefficient of the walks' inverse dynamics (an assumed value, for the slip report).
pub const WALK_MU: f64 = 0.5;

/// The inverse dynamics options the walks' plans are solved with: the planner's defaults, mu
/// [`WALK_MU`].
pub fn walk_dynamics() -> DynamicsOptions {
    DynamicsOptions {
        mu: WALK_MU,
        ..DynamicsOptions::default()
    }
}

/// The plan's inverse dynamics with [`walk_dynamics`], the plan checked finite first.
pub fn solve_walk_dynamics(plan: &Plan) -> Result<CycleSolution> {
    planner::plan::finite::check_plan(plan)
        .with_context(|| format!("planning a step of {}", plan.model.name))?;
    solve_cycle(&plan.model, &plan_inputs(plan), &walk_dynamics())
        .with_context(|| format!("inverse dynamics of {}", plan.model.name))
}

/// The paper's tripod (table 1, flat ground) of the built-in Drosophibot II as a step table
/// named `dbII tripod`, with the walks' inverse-dynamics torques as its bias: the gait the
/// validation's trial blocks and the lab's trial tests walk.
pub fn tripod_table() -> Result<Vec<u8>> {
    let model = planner::model::builtin("drosophibot2")?;
    let plan = planner::plan::plan(&model, &planner::gait::StepParams::table1(&model.name))?;
    let cycle = solve_walk_dynamics(&plan)?;
    let torques = planner::dynamics::output::torque_rows(&cycle);
    planner::plan::table::step_table(&plan, Some(&torques), "dbII tripod")
        .map_err(|e| crate::LabError::invalid(format!("the tripod's step table: {e}")))
}

/// Plays slot 0 for `steps` steps in `direction` at its planned period and records the walk into
/// `csv` (telemetry queued before the start is dropped); how the capture ended says whether it
/// was interrupted (`stop` returning true ends it early). A walk the board stopped on a fault is
/// an error naming the fault (its rows stay in `csv`): no figure is drawn from half a walk.
pub fn play_and_record<T: Transport>(
    board: &mut Board<T>,
    direction: Direction,
    steps: u32,
    csv: &Path,
    joints: Vec<JointMeta>,
    stop: impl Fn() -> bool,
) -> Result<(Recorder, Ended)> {
    board.discard_telemetry();
    // At its planned period: the period rule needs no table.
    crate::simulated::play(
        board,
        PlayCommand {
            slot: 0,
            direction,
            period_scale: protocol::units::PERIOD_SCALE_ONE,
            steps: Steps::Count(steps),
        },
        None,
    )?;
    let mut rec =
        Recorder::create(csv, joints).with_context(|| format!("creating {}", csv.display()))?;
    let ended = capture_while(
        board,
        &mut rec,
        Until {
            seconds: None,
            standing: true,
        },
        stop,
        |_| {},
    )?;
    if let Ended::Faulted(seen) = ended {
        crate::bail!(
            "{seen}; {} bus cycles recorded in {}",
            rec.cycles(),
            csv.display()
        );
    }
    Ok((rec, ended))
}

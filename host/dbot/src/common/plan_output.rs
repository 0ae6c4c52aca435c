//! Writing a plan directory, as `plan` and `demo` do: the planner's own files (plan.json,
//! model.toml, model.urdf, joints.csv, feet.csv: `planner::plan_dir`), the plan's plots, and with
//! the inverse dynamics its torque and force columns, joint_forces.csv and plots, and for a model
//! with gauges the predicted strain (strain.csv, strain.png).

use std::path::Path;

use anyhow::{Context, Result};
use planner::plan::Plan;
use planner::plan::feasibility::Feasibility;
use planner::plan_dir::{self, PlanJson};

use crate::common::output::replace;
use crate::common::plan_dynamics::PlanDynamics;

/// Writes `plan` (planned from the model `model_source`, its step table to be named `table_name`,
/// else after the directory) and its solved dynamics into `dir`; returns the names of the files
/// written.
pub fn write_plan_dir(
    dir: &Path,
    plan: &Plan,
    model_source: &str,
    table_name: Option<&str>,
    dynamics: Option<&PlanDynamics>,
    spring_args: serde_json::Value,
) -> Result<(Vec<&'static str>, Feasibility)> {
    let mut json = PlanJson::new(
        plan,
        model_source,
        table_name,
        dynamics.map(|d| d.json(plan)),
    );
    let torque = dynamics.map(|d| planner::dynamics::output::torque_rows(&d.cycle));
    let feasible =
        planner::plan::feasibility::check(&plan.model, &plan.q, torque.as_deref(), plan.dt);
    json.feasibility = Some(crate::feasibility_args::json(&feasible));
    json.spring_args = (!spring_args.is_null()).then_some(spring_args);
    let (joint_cols, feet_cols) =
        dynamics.map_or((vec![], vec![]), |d| (d.joint_columns(), d.feet_columns()));
    let mut files = plan_dir::write(dir, plan, &json, &joint_cols, &feet_cols)
        .with_context(|| format!("writing the plan directory {}", dir.display()))?
        .to_vec();
    replace(dir, "joint_angles.png", |p| {
        Ok(report::plan::plot_joint_angles(plan, p)?)
    })?;
    replace(dir, "footfall.png", |p| {
        Ok(report::plan::plot_footfall(plan, p)?)
    })?;
    replace(dir, "feet.png", |p| Ok(report::plan::plot_feet(plan, p)?))?;
    replace(dir, "robot.png", |p| {
        Ok(report::robot::plot_robot(plan, p).map(|_| ())?)
    })?;
    replace(dir, "step.gif", |p| {
        Ok(report::robot::animate_step(plan, p).map(|_| ())?)
    })?;
    replace(dir, "feasibility.md", |p| {
        Ok(std::fs::write(p, feasible.table())?)
    })?;
    replace(dir, "README.md", |p| {
        Ok(std::fs::write(p, report::PLAN_README)?)
    })?;
    files.extend([
        "joint_angles.png",
        "footfall.png",
        "feet.png",
        "robot.png",
        "step.gif",
        "feasibility.md",
        "README.md",
    ]);
    if let Some(d) = dynamics {
        files.extend(d.write_files(plan, dir)?);
        files.extend(write_strain(dir, plan, &d.cycle)?);
    }
    Ok((files, feasible))
}

/// strain.csv and strain.png, the gauges' predicted strain, when the model has gauges.
fn write_strain(
    dir: &Path,
    plan: &Plan,
    cycle: &planner::dynamics::CycleSolution,
) -> Result<Vec<&'static str>> {
    use planner::strain::csv::{STRAIN_CSV, write_strain_csv};
    if plan.model.gauges.is_empty() {
        return Ok(vec![]);
    }
    let strain = planner::strain::predict_plan(plan, cycle)?;
    replace(dir, STRAIN_CSV, |p| {
        let f = std::fs::File::create(p)?;
        Ok(write_strain_csv(f, &plan.model, plan.dt, &strain)?)
    })?;
    replace(dir, "strain.png", |p| {
        Ok(report::strain::plot_strain(plan, &strain, p)?)
    })?;
    Ok(vec![STRAIN_CSV, "strain.png"])
}

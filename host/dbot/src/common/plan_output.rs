//! Writing a plan directory, as `plan` and `demo` do: the planner's own files (plan.json,
//! model.toml, model.urdf, joints.csv, feet.csv: `planner::plan_dir`), the plan's plots, and with
//! the inverse dynamics its torque and force columns, joint_forces.csv and plots.

use std::path::Path;

use anyhow::{Context, Result};
use planner::plan::Plan;
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
) -> Result<Vec<&'static str>> {
    let json = PlanJson::new(
        plan,
        model_source,
        table_name,
        dynamics.map(|d| d.json(plan)),
    );
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
    files.extend(["joint_angles.png", "footfall.png", "feet.png"]);
    if let Some(d) = dynamics {
        files.extend(d.write_files(plan, dir)?);
    }
    Ok(files)
}

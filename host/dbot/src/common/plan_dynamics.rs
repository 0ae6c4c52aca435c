//! What the inverse dynamics adds to a plan's outputs: torque and servo-command columns in
//! joints.csv, GRF columns in feet.csv, joint_forces.csv, the plan.json summary and the torque /
//! GRF plots, and a one-line summary for the terminal.

use std::path::Path;

use anyhow::Result;
use planner::dynamics::{CycleSolution, DynamicsOptions, output};
use planner::plan::Plan;
use planner::plan_dir::{ExtraColumn, columns};

use crate::common::output::replace;

/// A solved cycle with its report columns.
#[derive(Debug, Clone)]
pub struct PlanDynamics {
    pub options: DynamicsOptions,
    pub cycle: CycleSolution,
    pub torque: Vec<Vec<f64>>,
    pub command: Vec<Vec<f64>>,
    pub grf: [Vec<Vec<f64>>; 3],
}

impl PlanDynamics {
    pub fn new(plan: &Plan, options: DynamicsOptions, cycle: CycleSolution) -> Self {
        let torque = output::torque_rows(&cycle);
        let command = plan
            .q
            .iter()
            .zip(&torque)
            .map(|(q, t)| output::biased_commands(&plan.model, q, t))
            .collect();
        let grf = output::grf_rows(&plan.model, &plan.legs, &cycle);
        Self {
            options,
            cycle,
            torque,
            command,
            grf,
        }
    }

    /// `torque_nm` and `command_rad` (angle + torque / servo stiffness) for joints.csv.
    pub fn joint_columns(&self) -> Vec<ExtraColumn<'_>> {
        vec![
            ExtraColumn {
                name: columns::TORQUE_NM,
                values: &self.torque,
            },
            ExtraColumn {
                name: columns::COMMAND_RAD,
                values: &self.command,
            },
        ]
    }

    /// `grf_x_n`, `grf_y_n`, `grf_z_n` for feet.csv.
    pub fn feet_columns(&self) -> Vec<ExtraColumn<'_>> {
        vec![
            ExtraColumn {
                name: columns::GRF_XYZ_N[0],
                values: &self.grf[0],
            },
            ExtraColumn {
                name: columns::GRF_XYZ_N[1],
                values: &self.grf[1],
            },
            ExtraColumn {
                name: columns::GRF_XYZ_N[2],
                values: &self.grf[2],
            },
        ]
    }

    /// The `dynamics` object of plan.json.
    pub fn json(&self, plan: &Plan) -> serde_json::Value {
        output::json_summary(&plan.model, &self.options, &self.cycle)
    }

    /// joint_forces.csv, torques.png, grf.png in `out`; returns the file names.
    /// Each file is written through [`crate::common::output::replace`]: a run that is killed leaves the
    /// previous file whole.
    pub fn write_files(&self, plan: &Plan, out: &Path) -> Result<Vec<&'static str>> {
        replace(out, columns::JOINT_FORCES_CSV, |p| {
            let f = std::fs::File::create(p)?;
            Ok(output::write_joint_forces_csv(
                f,
                &plan.model,
                plan.dt,
                &self.cycle,
            )?)
        })?;
        replace(out, "torques.png", |p| {
            Ok(report::dynamics::plot_torques(plan, &self.cycle, p)?)
        })?;
        replace(out, "grf.png", |p| {
            Ok(report::dynamics::plot_grf(plan, &self.cycle, p)?)
        })?;
        Ok(vec![columns::JOINT_FORCES_CSV, "torques.png", "grf.png"])
    }

    /// One line for the terminal: peak torque and what would slip or saturate.
    pub fn summary(&self) -> String {
        let peak = self
            .torque
            .iter()
            .flatten()
            .fold(0.0f64, |m, t| m.max(t.abs()));
        let r = &self.cycle.report;
        // The robot's torques are N m, the scale fly's are nano to micro N m.
        let peak = if peak >= 1e-2 {
            format!("{peak:.3}")
        } else {
            format!("{peak:.3e}")
        };
        format!(
            "peak actuated torque {peak} N m; {} foot-slices outside the mu = {} cone or pulling; {} joint-slices over the torque limit",
            r.slips.len(),
            self.options.mu,
            r.saturations.len()
        )
    }
}

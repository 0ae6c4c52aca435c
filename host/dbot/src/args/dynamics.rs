//! The inverse-dynamics flags of `dbot plan` and what the dynamics adds to a plan's outputs:
//! torque and servo-command columns in joints.csv, GRF columns in feet.csv, joint_forces.csv,
//! the plan.json summary and the torque / GRF plots.

use std::path::Path;

use anyhow::{Context, Result};
use planner::dynamics::{CycleSolution, DynamicsOptions, output, plan_inputs, solve_cycle};
use planner::plan::Plan;
use planner::plan_dir::{ExtraColumn, columns};

/// Inverse dynamics options (section 2.2.2 of the paper, solved as a QP per slice).
#[derive(Debug, Clone, clap::Args)]
pub struct DynamicsArgs {
    /// Skip the inverse dynamics (kinematics only).
    #[arg(long)]
    pub no_dynamics: bool,
    /// Keep each stance foot's GRF inside a friction cone |F_t| <= mu F_n (implies push-only).
    #[arg(long)]
    pub friction_cone: bool,
    /// Stance feet only push on the ground (F_n >= 0).
    #[arg(long)]
    pub push_only: bool,
    /// Friction coefficient for --friction-cone and the slip report (an assumed value).
    #[arg(long, default_value_t = 0.5)]
    pub mu: f64,
    /// Keep actuator torques within MX-28 2.5 N m and MX-64 6.0 N m.
    #[arg(long)]
    pub torque_limits: bool,
    /// Solve the slices on all cores.
    #[arg(long)]
    pub parallel: bool,
}

impl DynamicsArgs {
    pub fn options(&self) -> DynamicsOptions {
        DynamicsOptions {
            friction_cone: self.friction_cone,
            push_only: self.push_only,
            mu: self.mu,
            enforce_torque_limits: self.torque_limits,
            parallel: self.parallel,
            ..DynamicsOptions::default()
        }
    }

    /// Solve the plan's inverse dynamics unless --no-dynamics.
    pub fn solve(&self, plan: &Plan) -> Result<Option<PlanDynamics>> {
        if self.no_dynamics {
            return Ok(None);
        }
        let options = self.options();
        let cycle = solve_cycle(&plan.model, &plan_inputs(plan), &options)
            .with_context(|| format!("inverse dynamics of {}", plan.model.name))?;
        Ok(Some(PlanDynamics::new(plan, options, cycle)))
    }
}

/// A solved cycle with its report columns.
#[derive(Debug, Clone)]
pub struct PlanDynamics {
    pub options: DynamicsOptions,
    pub cycle: CycleSolution,
    torque: Vec<Vec<f64>>,
    command: Vec<Vec<f64>>,
    grf: [Vec<Vec<f64>>; 3],
}

impl PlanDynamics {
    fn new(plan: &Plan, options: DynamicsOptions, cycle: CycleSolution) -> Self {
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
        use crate::common::output::replace;
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

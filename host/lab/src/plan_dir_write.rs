//! The one writer of a plan directory, for `dbot plan`, `dbot demo` and Python's `Plan.write`:
//! the planner's own files (joints.csv, feet.csv, model.toml, model.urdf, then plan.json, in the
//! format `planner::plan_dir` reads), the plan's plots, feasibility.md and a README, and with the
//! inverse dynamics its torque and force columns, joint_forces.csv, the torque and GRF plots and,
//! for a model with gauges, the predicted strain (strain.csv, strain.png). Every file goes through
//! the one atomic write (`board::files::write_atomically`): a run that fails or is killed leaves
//! each file whole, from before or from this run.

use std::path::Path;

use board::files::write_atomically;
use planner::dynamics::{CycleSolution, DynamicsOptions, DynamicsSummary, output};
use planner::plan::Plan;
use planner::plan::feasibility::Feasibility;
use planner::plan::feasibility_summary::FeasibilitySummary;
use planner::plan_dir::columns::{FEET_CSV, JOINTS_CSV, MODEL_TOML, MODEL_URDF, PLAN_JSON};
use planner::plan_dir::{
    ExtraColumn, PlanJson, SpringOptions, columns, write_feet_csv, write_joints_csv,
};

use crate::error::{Context, Result};

/// A solved cycle with its report columns.
#[derive(Debug, Clone)]
pub struct PlanDynamics {
    pub options: DynamicsOptions,
    pub cycle: CycleSolution,
    /// Actuated torque per slice and joint, N m.
    pub torque: Vec<Vec<f64>>,
    /// Servo command (angle + torque / servo stiffness) per slice and joint, rad.
    pub command: Vec<Vec<f64>>,
    /// GRF `[x, y, z][slice][leg]`, N.
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

    /// `plan`'s inverse dynamics solved with `options`; a plan or a solution that is not finite
    /// is refused, naming the quantity, slice and joint.
    pub fn solve(plan: &Plan, options: DynamicsOptions) -> Result<Self> {
        use planner::plan::finite::{check_plan, check_rows};
        let what = || format!("inverse dynamics of {}", plan.model.name);
        check_plan(plan).with_context(|| format!("planning a step of {}", plan.model.name))?;
        let inputs = planner::dynamics::plan_inputs(plan);
        let cycle =
            planner::dynamics::solve_cycle(&plan.model, &inputs, &options).with_context(what)?;
        let d = Self::new(plan, options, cycle);
        let joints: Vec<String> = plan.model.joints.iter().map(|j| j.name.clone()).collect();
        check_rows("joint torque", &d.torque, &joints).with_context(what)?;
        check_rows("servo command", &d.command, &joints).with_context(what)?;
        for (axis, rows) in ["x", "y", "z"].iter().zip(&d.grf) {
            check_rows("ground reaction force", rows, &[])
                .with_context(|| format!("{} (GRF {axis})", what()))?;
        }
        Ok(d)
    }

    /// `torque_nm` and `command_rad` for joints.csv.
    fn joint_columns(&self) -> Vec<ExtraColumn<'_>> {
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
    fn feet_columns(&self) -> Vec<ExtraColumn<'_>> {
        (0..3)
            .map(|axis| ExtraColumn {
                name: columns::GRF_XYZ_N[axis],
                values: &self.grf[axis],
            })
            .collect()
    }

    /// One line for a terminal: peak torque and what would slip or saturate.
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

/// What a plan directory was planned from and is to be called.
#[derive(Debug, Clone, Default)]
pub struct PlanSource<'a> {
    /// The model as given to the planner (a built-in name or a file path).
    pub model_source: &'a str,
    /// The name its step table gets (else the directory's).
    pub table_name: Option<&'a str>,
    /// The `--spring` options the model was planned with.
    pub spring: Option<SpringOptions>,
}

/// What [`write_plan_dir`] wrote.
#[derive(Debug, Clone)]
pub struct WrittenPlan {
    /// The files' names, in the order written.
    pub files: Vec<&'static str>,
    /// The servos against the plan (as in plan.json and feasibility.md).
    pub feasibility: Feasibility,
}

/// Writes `plan` and, if given, its solved dynamics into `dir` (created if missing).
pub fn write_plan_dir(
    dir: &Path,
    plan: &Plan,
    source: &PlanSource<'_>,
    dynamics: Option<&PlanDynamics>,
) -> Result<WrittenPlan> {
    let torque = dynamics.map(|d| d.torque.as_slice());
    let feasibility = planner::plan::feasibility::check(&plan.model, &plan.q, torque, plan.dt);
    let mut json = PlanJson::new(
        plan,
        source.model_source,
        source.table_name,
        dynamics.map(|d| DynamicsSummary::new(&plan.model, &d.options, &d.cycle)),
    );
    json.feasibility = Some(FeasibilitySummary::new(&feasibility));
    json.spring_args = source.spring.clone();
    let mut files = write_planner_files(dir, plan, &json, dynamics)
        .with_context(|| format!("writing the plan directory {}", dir.display()))?;
    let write = |name: &'static str, f: &dyn Fn(&Path) -> Result<(), board::files::WriteError>| {
        write_atomically(&dir.join(name), f).map(|()| name)
    };
    files.push(write("joint_angles.png", &|p| {
        Ok(report::plan::plot_joint_angles(plan, p)?)
    })?);
    files.push(write("footfall.png", &|p| {
        Ok(report::plan::plot_footfall(plan, p)?)
    })?);
    files.push(write("feet.png", &|p| {
        Ok(report::plan::plot_feet(plan, p)?)
    })?);
    files.push(write("robot.png", &|p| {
        Ok(report::robot::plot_robot(plan, p).map(|_| ())?)
    })?);
    files.push(write("step.gif", &|p| {
        Ok(report::robot::animate_step(plan, p).map(|_| ())?)
    })?);
    files.push(write("feasibility.md", &|p| {
        Ok(std::fs::write(p, feasibility.table())?)
    })?);
    files.push(write("README.md", &|p| {
        Ok(std::fs::write(p, report::PLAN_README)?)
    })?);
    if let Some(d) = dynamics {
        files.push(write(columns::JOINT_FORCES_CSV, &|p| {
            let f = std::fs::File::create(p)?;
            Ok(output::write_joint_forces_csv(
                f,
                &plan.model,
                plan.dt,
                &d.cycle,
            )?)
        })?);
        files.push(write("torques.png", &|p| {
            Ok(report::dynamics::plot_torques(plan, &d.cycle, p)?)
        })?);
        files.push(write("grf.png", &|p| {
            Ok(report::dynamics::plot_grf(plan, &d.cycle, p)?)
        })?);
        if !plan.model.gauges.is_empty() {
            use planner::strain::csv::{STRAIN_CSV, write_strain_csv};
            let strain = planner::strain::predict_plan(plan, &d.cycle)?;
            files.push(write(STRAIN_CSV, &|p| {
                let f = std::fs::File::create(p)?;
                Ok(write_strain_csv(f, &plan.model, plan.dt, &strain)?)
            })?);
            files.push(write("strain.png", &|p| {
                Ok(report::strain::plot_strain(plan, &strain, p)?)
            })?);
        }
    }
    Ok(WrittenPlan { files, feasibility })
}

/// The files `planner::plan_dir::read` reads, plan.json last: a directory with a plan.json of
/// this format has all its other files.
fn write_planner_files(
    dir: &Path,
    plan: &Plan,
    json: &PlanJson,
    dynamics: Option<&PlanDynamics>,
) -> Result<Vec<&'static str>> {
    std::fs::create_dir_all(dir)?;
    let (joint_cols, feet_cols) =
        dynamics.map_or((vec![], vec![]), |d| (d.joint_columns(), d.feet_columns()));
    write_atomically(&dir.join(JOINTS_CSV), |p| {
        Ok(write_joints_csv(
            std::fs::File::create(p)?,
            plan,
            &joint_cols,
        )?)
    })?;
    write_atomically(&dir.join(FEET_CSV), |p| {
        Ok(write_feet_csv(std::fs::File::create(p)?, plan, &feet_cols)?)
    })?;
    let notes = format!(
        "The model of this plan directory (planned from `{}`), written with the plan so the \
         directory is read without the model's source.",
        json.model_source
    );
    let toml = planner::model::to_toml_string(&plan.model, &notes, &|_| String::new());
    write_atomically(&dir.join(MODEL_TOML), |p| Ok(std::fs::write(p, &toml)?))?;
    let urdf = planner::model::to_urdf(&plan.model);
    write_atomically(&dir.join(MODEL_URDF), |p| Ok(std::fs::write(p, &urdf)?))?;
    let text = json.to_json();
    write_atomically(&dir.join(PLAN_JSON), |p| Ok(std::fs::write(p, &text)?))?;
    Ok(vec![
        JOINTS_CSV, FEET_CSV, MODEL_TOML, MODEL_URDF, PLAN_JSON,
    ])
}

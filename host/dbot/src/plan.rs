//! `dbot plan`: plan one step cycle and write joints.csv, feet.csv, plan.json, model.urdf, plots
//! and the robot drawn in three views (robot.png, step.gif).

use crate::common::model_spec::load_model;
use anyhow::{Context, Result};
use indicatif::ProgressBar;
use planner::gait::{Gait, ParamsFile, StepParams};
use planner::plan_dir;
use std::path::{Path, PathBuf};

use crate::common::output::replace;

/// Plan a step cycle: resting posture, footpaths, inverse kinematics, velocities, accelerations.
///
/// Stepping parameters default to table 1 of the paper for the model; a --params TOML file
/// overrides any of them, and the flags below override the file.
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot plan --out out/walk                                   # Drosophibot II, tripod, flat ground, table 1
  dbot plan --model scale-drosophila --terrain ball --out out/fly-ball   # the fly on the ball
  dbot plan --params lab-step.toml --no-dynamics --out out/quick")]
pub struct Args {
    #[command(flatten)]
    model: crate::args::setup::ModelArgs,
    /// flat, ball[:RADIUS_M[:OFFSET_M]] (m) or incline:DEG (degrees). Default: table 1 (flat).
    #[arg(long)]
    terrain: Option<String>,
    /// tripod, tetrapod, wave or PHI_I:PHI_C (fractions of the cycle). Default: table 1 (tripod).
    #[arg(long)]
    gait: Option<String>,
    /// Swing duration, s. Default: table 1 of the paper for the model (drosophibot2 0.5 s,
    /// scale-drosophila 0.1 s).
    #[arg(long, allow_negative_numbers = true)]
    swing: Option<f64>,
    /// Time slices per step cycle. Default: table 1 (100).
    #[arg(long)]
    slices: Option<usize>,
    /// Body height offsets per leg pair, HIND,MIDDLE,FRONT in m, added to the preset's (table 1's
    /// note: the physical robot varies body height per pair against sag and backlash).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    body_height_offset: Option<Vec<f64>>,
    /// Walk backward (negates the body translation per step).
    #[arg(long)]
    backward: bool,
    /// Stepping-parameter preset the file and flags below start from: table1 (default),
    /// physical-robot (Drosophibot II as the original solver ran it: per-pair body heights and
    /// its resting feet, swing 1.6 s) or paper-comparison (the paper's robot-vs-fly conditions).
    #[arg(long, default_value = "table1")]
    preset: String,
    /// TOML file with stepping parameters, any subset of: swing_s (s), duty, step_height_m and
    /// body_height_m ({ hind, middle, front }, m), translation_m and rotation_rad (per stance),
    /// gait ({ phi_i, phi_c }), slices, terrain, ball_radius_m, ball_offset_m (below the CoM, m),
    /// placement ({ forward_m = {..}, outward_m = {..} }, foot offsets from each ThC, m).
    #[arg(long)]
    params: Option<PathBuf>,
    /// Output directory (created if missing).
    #[arg(long)]
    out: PathBuf,
    #[command(flatten)]
    dynamics: crate::args::dynamics::DynamicsArgs,
    #[command(flatten)]
    springs: crate::spring_args::SpringArgs,
}

impl Args {
    pub fn run(self) -> Result<()> {
        let spec = self.model.spec()?;
        let model = self.springs.apply(load_model(&spec)?)?;
        let mut p = StepParams::preset(&self.preset, &model.name).with_context(|| {
            format!(
                "--preset {}: expected one of {} (physical-robot is for drosophibot2)",
                self.preset,
                planner::gait::PRESETS.join(", ")
            )
        })?;
        if let Some(f) = &self.params {
            let text =
                std::fs::read_to_string(f).with_context(|| format!("reading {}", f.display()))?;
            ParamsFile::from_toml(&text, &f.display().to_string())?.apply(&mut p);
        }
        if let Some(t) = self.terrain {
            p.terrain = t;
        }
        if let Some(g) = &self.gait {
            p.gait = Gait::parse(g).with_context(|| {
                format!("--gait `{g}`: expected tripod, tetrapod, wave or PHI_I:PHI_C")
            })?;
        }
        if let Some(s) = self.swing {
            p.swing_s = s;
        }
        if let Some(n) = self.slices {
            p.slices = n;
        }
        if let Some(o) = &self.body_height_offset {
            if o.len() != 3 || !o.iter().all(|v| v.is_finite()) {
                anyhow::bail!(
                    "--body-height-offset takes three offsets HIND,MIDDLE,FRONT in m, got {o:?}"
                );
            }
            p.body_height_m.hind += o[0];
            p.body_height_m.middle += o[1];
            p.body_height_m.front += o[2];
        }
        if self.backward {
            p.translation_m = -p.translation_m.abs();
        }
        crate::bounds::check_slices("slices", p.slices, crate::bounds::table_joints(&model))?;
        if p.slices > crate::bounds::TELL_ABOVE_SLICES {
            eprintln!(
                "planning {} slices of {} (the inverse dynamics solves one QP per slice)",
                p.slices, model.name
            );
        }
        let bar = ProgressBar::new(7);
        bar.set_message("planning");
        let plan = planner::plan::plan(&model, &p)
            .with_context(|| format!("planning a step of {}", model.name))?;
        planner::plan::finite::check_plan(&plan)
            .with_context(|| format!("planning a step of {}", model.name))?;
        bar.inc(1);
        let dynamics = self.dynamics.solve(&plan)?;
        let out = &self.out;
        std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
        let (joint_cols, feet_cols) = dynamics
            .as_ref()
            .map_or((vec![], vec![]), |d| (d.joint_columns(), d.feet_columns()));
        let file = |p: &Path| std::fs::File::create(p).map_err(anyhow::Error::from);
        replace(out, "joints.csv", |p| {
            Ok(plan_dir::write_joints_csv(file(p)?, &plan, &joint_cols)?)
        })?;
        replace(out, "feet.csv", |p| {
            Ok(plan_dir::write_feet_csv(file(p)?, &plan, &feet_cols)?)
        })?;
        bar.inc(1);
        let mut json = serde_json::json!({
            "model": model.name,
            "model_source": spec,
            "spring_args": self.springs.json(),
            "parameters": plan.params,
            "terrain": plan.terrain,
            "gravity_m_s2": plan.gravity,
            "ball_centre_m": plan.ball_centre,
            "period_s": plan.period_s,
            "dt_s": plan.dt,
            "slices": plan.slices(),
            "legs": plan.legs,
            "leg_phases": plan.phases,
            "thorax_velocity_m_s": plan.thorax_velocity,
            "thorax_angular_velocity_rad_s": plan.thorax_angular_velocity,
            "resting_posture_rad": model.joints.iter().zip(&plan.posture.q).map(|(j, q)| (j.name.clone(), *q)).collect::<std::collections::BTreeMap<_, _>>(),
            "frames": "thorax frame, REP-103: x forward, y left, z up; SI units",
        });
        if let Some(d) = &dynamics {
            json["dynamics"] = d.json(&plan);
        }
        let torque = dynamics
            .as_ref()
            .map(|d| planner::dynamics::output::torque_rows(&d.cycle));
        let feasible =
            planner::plan::feasibility::check(&plan.model, &plan.q, torque.as_deref(), plan.dt);
        json["feasibility"] = crate::feasibility_args::json(&feasible);
        replace(out, "feasibility.md", |p| {
            Ok(std::fs::write(p, feasible.table())?)
        })?;
        let json = serde_json::to_string_pretty(&json)?;
        replace(out, "plan.json", |p| Ok(std::fs::write(p, &json)?))?;
        replace(out, "README.md", |p| {
            Ok(std::fs::write(p, report::PLAN_README)?)
        })?;
        let urdf = planner::model::to_urdf(&model);
        replace(out, "model.urdf", |p| Ok(std::fs::write(p, &urdf)?))?;
        bar.inc(1);
        replace(out, "joint_angles.png", |p| {
            Ok(report::plan::plot_joint_angles(&plan, p)?)
        })?;
        bar.inc(1);
        replace(out, "footfall.png", |p| {
            Ok(report::plan::plot_footfall(&plan, p)?)
        })?;
        bar.inc(1);
        replace(out, "feet.png", |p| Ok(report::plan::plot_feet(&plan, p)?))?;
        replace(out, "robot.png", |p| {
            Ok(report::robot::plot_robot(&plan, p).map(|_| ())?)
        })?;
        replace(out, "step.gif", |p| {
            Ok(report::robot::animate_step(&plan, p).map(|_| ())?)
        })?;
        if let Some(d) = &dynamics {
            let files = d.write_files(&plan, out)?;
            println!("{}; wrote {}", d.summary(), files.join(" "));
        }
        bar.finish_and_clear();
        println!("{}", crate::feasibility_args::summary(&feasible));
        println!(
            "{}: {} slices, period {:.3} s, wrote README.md joints.csv feet.csv plan.json feasibility.md model.urdf joint_angles.png footfall.png feet.png robot.png step.gif to {}",
            model.name,
            plan.slices(),
            plan.period_s,
            out.display()
        );
        Ok(())
    }
}

//! `dbot plan`: plan one step cycle and write joints.csv, feet.csv, plan.json, model.urdf and plots.

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
    /// Walk backward (negates the body translation per step).
    #[arg(long)]
    backward: bool,
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
}

impl Args {
    pub fn run(self) -> Result<()> {
        let spec = self.model.spec()?;
        let model = load_model(&spec)?;
        let mut p = StepParams::table1(&model.name);
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
        if self.backward {
            p.translation_m = -p.translation_m.abs();
        }
        let bar = ProgressBar::new(6);
        bar.set_message("planning");
        let plan = planner::plan::plan(&model, &p)
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
        let json = serde_json::to_string_pretty(&json)?;
        replace(out, "plan.json", |p| Ok(std::fs::write(p, &json)?))?;
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
        if let Some(d) = &dynamics {
            let files = d.write_files(&plan, out)?;
            println!("{}; wrote {}", d.summary(), files.join(" "));
        }
        bar.finish_and_clear();
        println!(
            "{}: {} slices, period {:.3} s, wrote joints.csv feet.csv plan.json model.urdf joint_angles.png footfall.png feet.png to {}",
            model.name,
            plan.slices(),
            plan.period_s,
            out.display()
        );
        Ok(())
    }
}

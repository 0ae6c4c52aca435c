//! `dbot plan`: plan one step cycle and write it as a plan directory (plan.json, model.toml,
//! joints.csv, feet.csv, model.urdf, plots; with the inverse dynamics its columns and files too).

use crate::common::model_spec::load_model;
use anyhow::{Context, Result, bail};
use indicatif::ProgressBar;
use planner::gait::{Gait, ParamsFile, StepParams};
use std::path::PathBuf;

use crate::common::plan_output::write_plan_dir;

/// Plan a step cycle: resting posture, footpaths, inverse kinematics, velocities, accelerations.
///
/// Stepping parameters default to table 1 of the paper for the model; a --params TOML file
/// overrides any of them, and the flags below override the file.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Built-in model name (drosophibot2, scale-drosophila), a .toml model or an .aproj file.
    #[arg(long, default_value = "drosophibot2")]
    model: String,
    /// flat, ball[:RADIUS_M[:OFFSET_M]] or incline:DEG.
    #[arg(long)]
    terrain: Option<String>,
    /// tripod, tetrapod, wave or PHI_I:PHI_C (fractions of the cycle).
    #[arg(long)]
    gait: Option<String>,
    /// Swing duration, s.
    #[arg(long)]
    swing: Option<f64>,
    /// Time slices per step cycle.
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
    /// Output directory (created if missing): the plan directory that `table`, `compare` and
    /// `upload --plan` read.
    #[arg(long)]
    out: PathBuf,
    /// Gait name of the step tables built from this plan (at most 16 bytes); default: the plan
    /// directory's name when a table is built from it.
    #[arg(long)]
    name: Option<String>,
    #[command(flatten)]
    dynamics: crate::args::dynamics::DynamicsArgs,
}

impl Args {
    pub fn run(self) -> Result<()> {
        let model = load_model(&self.model)?;
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
        let bar = ProgressBar::new(2);
        bar.set_message("planning");
        let plan = planner::plan::plan(&model, &p)
            .with_context(|| format!("planning a step of {}", model.name))?;
        bar.inc(1);
        let dynamics = self.dynamics.solve(&plan)?;
        bar.inc(1);
        let out = &self.out;
        if let Some(n) = self
            .name
            .as_ref()
            .filter(|n| n.len() > protocol::gait::NAME_LEN)
        {
            bail!(
                "--name `{n}`: a gait name has at most {} bytes",
                protocol::gait::NAME_LEN
            );
        }
        let files = write_plan_dir(
            out,
            &plan,
            &self.model,
            self.name.as_deref(),
            dynamics.as_ref(),
        )?;
        bar.finish_and_clear();
        if let Some(d) = &dynamics {
            println!("{}", d.summary());
        }
        println!(
            "{}: {} slices, period {:.3} s, wrote {} to {}",
            model.name,
            plan.slices(),
            plan.period_s,
            files.join(" "),
            out.display()
        );
        Ok(())
    }
}

//! `dbot plan`: plan one step cycle and write it as a plan directory (plan.json, model.toml,
//! joints.csv, feet.csv, feasibility.md, model.urdf, plots, the robot drawn in three views and a
//! step animation; with the inverse dynamics its columns and files too).

use crate::common::model_spec::load_model;
use anyhow::{Context, Result, bail};
use indicatif::ProgressBar;
use planner::gait::{Gait, ParamsFile, StepParams};
use std::path::PathBuf;

use lab::plan_dir_write::{PlanSource, write_plan_dir};

/// Above this many slices a plan says what it is doing (the inverse dynamics solves one QP per
/// slice: tens of seconds for a few thousand in a debug build).
const TELL_ABOVE_SLICES: usize = 500;

/// Plan a step cycle: resting posture, footpaths, inverse kinematics, velocities, accelerations.
///
/// Stepping parameters default to table 1 of the paper for the model at a swing the servos can
/// follow (--preset servo-safe); a --params TOML file overrides any of them, and the flags below
/// override the file.
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot plan --out out/walk                                   # Drosophibot II, tripod, flat ground, table 1, swing 1.0 s
  dbot plan --model scale-drosophila --terrain ball --out out/fly-ball   # the fly on the ball
  dbot plan --params lab-step.toml --no-dynamics --out out/quick
  dbot plan --radius 0.5 --out out/curve-left                 # a left curve on 0.5 m, the stride kept
  dbot plan --turn -20 --radius 0 --out out/spin-right        # on the spot, 20 deg right per step")]
pub struct Args {
    #[command(flatten)]
    model: crate::args::setup::ModelArgs,
    /// flat, ball[:RADIUS_M[:OFFSET_M]] (m) or incline:DEG (degrees); the physics robot's other
    /// scenes (ball-fixed, blocks) are refused, saying so. Default: table 1 (flat).
    #[arg(long)]
    terrain: Option<planner::terrain::Ground>,
    /// tripod, tetrapod, wave or PHI_I:PHI_C (fractions of the cycle). Default: table 1 (tripod).
    #[arg(long)]
    gait: Option<String>,
    /// Swing duration, s. Default: the preset's (servo-safe: drosophibot2 1.0 s, scale-drosophila
    /// 0.1 s; table1: drosophibot2 0.5 s).
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
    /// Turn: the thorax's yaw per step, deg, positive left, between -180 and 180 (exclusive).
    /// Alone it keeps the stride (radius = stride / turn); with --radius it sets the stride.
    #[arg(long, value_name = "DEG_PER_STEP", allow_negative_numbers = true)]
    turn: Option<f64>,
    /// Turn on a radius: the thorax path's radius, m, positive with the centre on the left,
    /// between -100 and 100. Alone it keeps the stride and sets the turn (stride / radius); with
    /// --turn the stride is radius x turn, and --radius 0 turns on the spot.
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    radius: Option<f64>,
    /// Stepping-parameter preset the file and flags below start from: servo-safe (default; table
    /// 1 at a 1.0 s swing, which the servos follow with at least 26 % speed headroom), table1
    /// (swing 0.5 s, the original solver's default: too fast for the front servos),
    /// physical-robot (Drosophibot II as the original solver ran it: per-pair body heights and
    /// its resting feet, swing 1.6 s) or paper-comparison (the paper's robot-vs-fly conditions).
    #[arg(long, default_value = planner::gait::DEFAULT_PRESET)]
    preset: String,
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
            if self.turn.is_some() && self.radius.is_some() {
                bail!(
                    "--backward with --turn and --radius: the stride is then radius x turn and \
                     their signs give the direction (a right radius with a left turn walks backward)"
                );
            }
            p.translation_m = -p.translation_m.abs();
        }
        planner::gait::Turn {
            turn_deg: self.turn,
            radius_m: self.radius,
        }
        .apply(&mut p)
        .context("--turn/--radius")?;
        use board::rules::slots::{check_slices, table_joints};
        check_slices("slices", p.slices, table_joints(&model))?;
        if p.slices > TELL_ABOVE_SLICES {
            eprintln!(
                "planning {} slices of {} (the inverse dynamics solves one QP per slice)",
                p.slices, model.name
            );
        }
        let bar = ProgressBar::new(2);
        bar.set_message("planning");
        let plan = planner::plan::plan(&model, &p)
            .with_context(|| format!("planning a step of {}", model.name))?;
        planner::plan::finite::check_plan(&plan)
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
        let source = PlanSource {
            model_source: &spec,
            table_name: self.name.as_deref(),
            spring: self.springs.options(),
        };
        let written = write_plan_dir(out, &plan, &source, dynamics.as_ref())?;
        bar.finish_and_clear();
        println!(
            "{}: {} slices, period {:.3} s, wrote {} to {}",
            model.name,
            plan.slices(),
            plan.period_s,
            written.files.join(" "),
            out.display()
        );
        if let Some(d) = &dynamics {
            println!("{}", d.summary());
        }
        println!("{}", crate::feasibility_args::summary(&written.feasibility));
        if !plan.ik_gaps.is_empty() {
            println!(
                "inverse kinematics: {} run(s) of steps over a joint's speed allowance:",
                plan.ik_gaps.len()
            );
            for g in &plan.ik_gaps {
                println!("  {g}");
            }
        }
        Ok(())
    }
}

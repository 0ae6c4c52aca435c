//! `dbot compare`: R-squared of angle and torque regressions per common DoF of two plans
//! (tables S2 to S8 of the paper) with overlaid plots, or a speed sweep over swing durations.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use planner::analysis::{DofTrace, classify_sweep, compare};
use planner::model::{JointKind, Leg};
use planner::plan_dir::{self, columns};

use crate::common::output::replace;
use crate::common::overlay::{folder_name, overlay};

/// Compare two plans DoF by DoF, or sweep the swing duration of one model.
///
/// With two plan directories (written by `dbot plan`, with torques): per common DoF the R-squared
/// of a linear regression of the angles and of the torques, plus ThC2+CTr summed where one
/// organism elevates with both; writes compare.csv, compare_angles.png, compare_torques.png.
/// With --swing S1,S2,..: plans --model at each swing duration and reports how the peak torque
/// and its inertial part scale with the step period (quasi-static or inertial regime).
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot compare out/walk out/fly-ball                  # writes out/compare/compare.csv and plots
  dbot compare --swing 0.4,0.8,1.6 --out out/sweep    # the speed sweep of Drosophibot II")]
pub struct Args {
    /// Plan directories A and B (from `dbot plan` or `dbot demo`, with torques).
    #[arg(num_args = 0..=2)]
    plans: Vec<PathBuf>,
    /// Swing durations for a speed sweep, s, comma separated.
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    swing: Vec<f64>,
    /// The model of the sweep (--model, else the setup file's, else drosophibot2).
    #[command(flatten)]
    model: crate::args::setup::ModelArgs,
    /// Output directory (created if missing).
    #[arg(long, default_value = "out/compare")]
    out: PathBuf,
    /// The paper's comparison (tables S2 to S8, figures 4 and S7 with and without parallel
    /// springs, ball vs flat GRF) in one run: robot at a 4 s period, fly at table 1's 0.25 s.
    #[arg(long)]
    paper: bool,
    /// Time slices per step for --paper.
    #[arg(long, default_value_t = 100)]
    slices: usize,
}

impl Args {
    pub fn run(self) -> Result<()> {
        if self.paper {
            if !self.plans.is_empty() || !self.swing.is_empty() {
                bail!("--paper runs its own plans: give no plan directories and no --swing");
            }
            std::fs::create_dir_all(&self.out)
                .with_context(|| format!("creating {}", self.out.display()))?;
            let c = crate::compare_paper::run_paper(&self.out, self.slices)?;
            println!("{}", c.markdown);
            println!(
                "wrote tables.md tables.csv and per-case plots to {}",
                self.out.display()
            );
            return Ok(());
        }
        let two_plans = self.plans.len() == 2 && self.swing.is_empty();
        let sweep_only = self.plans.is_empty() && !self.swing.is_empty();
        if !(two_plans || sweep_only) {
            bail!("give either two plan directories or --swing S1,S2,... (not both)");
        }
        std::fs::create_dir_all(&self.out)
            .with_context(|| format!("creating {}", self.out.display()))?;
        match (self.plans.len(), self.swing.is_empty()) {
            (2, true) => compare_dirs(&self.plans[0], &self.plans[1], &self.out),
            (0, false) => sweep(&self.model.spec()?, &self.swing, &self.out),
            _ => bail!("give either two plan directories or --swing S1,S2,... (not both)"),
        }
    }
}

/// DoF traces of a plan directory (torques required): one per model joint, keyed by leg and kind.
fn read_traces(dir: &Path) -> Result<Vec<DofTrace>> {
    let plan = plan_dir::read(dir)?;
    let torque = plan.torque.as_ref().with_context(|| {
        format!(
            "{}: no `{}` column (planned with --no-dynamics?)",
            dir.join(columns::JOINTS_CSV).display(),
            columns::TORQUE_NM
        )
    })?;
    let mut map: BTreeMap<(Leg, JointKind), (Vec<f64>, Vec<f64>)> = BTreeMap::new();
    for (angles, torques) in plan.angle.iter().zip(torque) {
        for (joint, (a, t)) in plan.model.joints.iter().zip(angles.iter().zip(torques)) {
            let e = map.entry((joint.leg, joint.kind)).or_default();
            e.0.push(*a);
            e.1.push(*t);
        }
    }
    Ok(map
        .into_iter()
        .map(|((leg, kind), (angle, torque))| {
            let (lo, hi) = angle
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), a| {
                    (l.min(*a), h.max(*a))
                });
            DofTrace {
                leg,
                kind,
                mobile: hi - lo > 1e-9,
                angle,
                torque,
            }
        })
        .collect())
}

fn fmt(v: Option<f64>) -> String {
    v.map_or("-".into(), |v| format!("{v:.3}"))
}

fn compare_dirs(a: &Path, b: &Path, out: &Path) -> Result<()> {
    let (ta, tb) = (read_traces(a)?, read_traces(b)?);
    let rows = compare(&ta, &tb);
    if rows.is_empty() {
        bail!("{} and {} have no DoF in common", a.display(), b.display());
    }
    // Built in memory and written through a scratch file: a killed run leaves the old file whole.
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(["leg", "dof", "summed_in", "r2_angle", "r2_torque"])?;
    println!("| leg | DoF | R^2 angle | R^2 torque |\n|---|---|---|---|");
    for r in &rows {
        let summed = match r.summed_side {
            Some(0) => "A",
            Some(_) => "B",
            None => "",
        };
        w.write_record([
            r.leg.name(),
            &r.dof,
            summed,
            &fmt(r.r2_angle),
            &fmt(r.r2_torque),
        ])?;
        let label = if summed.is_empty() {
            r.dof.clone()
        } else {
            format!("{} (sum in {summed})", r.dof)
        };
        println!(
            "| {} | {label} | {} | {} |",
            r.leg.name(),
            fmt(r.r2_angle),
            fmt(r.r2_torque)
        );
    }
    let bytes = w.into_inner().context("building compare.csv")?;
    replace(out, "compare.csv", |p| Ok(std::fs::write(p, &bytes)?))?;
    overlay(&ta, &tb, &rows, out, [&folder_name(a), &folder_name(b)])?;
    println!(
        "wrote compare.csv compare_angles.png compare_torques.png to {}",
        out.display()
    );
    Ok(())
}

fn sweep(model: &str, swings: &[f64], out: &Path) -> Result<()> {
    let model = crate::common::model_spec::load_model(model)?;
    let mut points = Vec::new();
    let bar = indicatif::ProgressBar::new(swings.len() as u64);
    for &sw in swings {
        if !(sw > 0.0 && sw.is_finite()) {
            bail!("--swing {sw}: swing durations must be positive seconds");
        }
        let mut p = planner::gait::StepParams::table1(&model.name);
        p.swing_s = sw;
        points.push(planner::analysis::sweep_point(&model, &p)?);
        bar.inc(1);
    }
    bar.finish_and_clear();
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "period_s",
        "peak_torque_nm",
        "peak_inertial_torque_nm",
        "inertial_share",
    ])?;
    println!("| period (s) | peak torque (N m) | inertial part (N m) | share |\n|---|---|---|---|");
    for p in &points {
        let share = p.peak_inertial_torque / p.peak_torque;
        w.write_record(
            [p.period, p.peak_torque, p.peak_inertial_torque, share]
                .map(|v| planner::number::plain(v, 7)),
        )?;
        println!(
            "| {:.3} | {:.4e} | {:.4e} | {:.3} |",
            p.period, p.peak_torque, p.peak_inertial_torque, share
        );
    }
    let bytes = w.into_inner().context("building sweep.csv")?;
    replace(out, "sweep.csv", |p| Ok(std::fs::write(p, &bytes)?))?;
    if let Some(r) = classify_sweep(&points) {
        println!(
            "inertial torque ~ T^{:.2} (-2 for pure inertia); quasi-static where the inertial share is below ~0.1",
            r.inertial_exponent
        );
    }
    println!("wrote sweep.csv to {}", out.display());
    Ok(())
}

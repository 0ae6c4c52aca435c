//! `dbot compare`: R-squared of angle and torque regressions per common DoF of two plans
//! (tables S2 to S8 of the paper) with overlaid plots, or a speed sweep over swing durations.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use planner::analysis::{ComparisonRow, DofTrace, SweepPoint, classify_sweep, compare};
use planner::dynamics::{DynamicsOptions, plan_inputs, solve_cycle};
use planner::model::{JointKind, Leg};
use planner::plan_dir::{self, columns};
use report::legs::{Panel, Trace, plot_leg_panels};

use crate::common::output::replace;

/// Compare two plans DoF by DoF, or sweep the swing duration of one model.
///
/// With two plan directories (written by `dbot plan`, with torques): per common DoF the R-squared
/// of a linear regression of the angles and of the torques, plus ThC2+CTr summed where one
/// organism elevates with both; writes compare.csv, compare_angles.png, compare_torques.png.
/// With --swing S1,S2,..: plans --model at each swing duration and reports how the peak torque
/// and its inertial part scale with the step period (quasi-static or inertial regime).
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Plan directories A and B (from `dbot plan` or `dbot demo`, with torques).
    #[arg(num_args = 0..=2)]
    plans: Vec<PathBuf>,
    /// Swing durations for a speed sweep, s, comma separated.
    #[arg(long, value_delimiter = ',')]
    swing: Vec<f64>,
    /// Model of the sweep: built-in name, .toml or .aproj.
    #[arg(long, default_value = "drosophibot2")]
    model: String,
    /// Output directory (created if missing).
    #[arg(long)]
    out: PathBuf,
}

impl Args {
    pub fn run(self) -> Result<()> {
        let two_plans = self.plans.len() == 2 && self.swing.is_empty();
        let sweep_only = self.plans.is_empty() && !self.swing.is_empty();
        if !(two_plans || sweep_only) {
            bail!("give either two plan directories or --swing S1,S2,... (not both)");
        }
        std::fs::create_dir_all(&self.out)
            .with_context(|| format!("creating {}", self.out.display()))?;
        match (self.plans.len(), self.swing.is_empty()) {
            (2, true) => compare_dirs(&self.plans[0], &self.plans[1], &self.out),
            (0, false) => sweep(&self.model, &self.swing, &self.out),
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
    overlay(&ta, &tb, &rows, out)?;
    println!(
        "wrote compare.csv compare_angles.png compare_torques.png to {}",
        out.display()
    );
    Ok(())
}

/// Angle (deg) overlays and torque overlays normalised by each plan's peak torque, A solid, B dashed.
fn overlay(ta: &[DofTrace], tb: &[DofTrace], rows: &[ComparisonRow], out: &Path) -> Result<()> {
    let n = ta
        .iter()
        .chain(tb)
        .map(|d| d.angle.len())
        .max()
        .unwrap_or(1);
    let peak = |t: &[DofTrace]| {
        t.iter()
            .flat_map(|d| &d.torque)
            .fold(0.0f64, |m, v| m.max(v.abs()))
            .max(f64::MIN_POSITIVE)
    };
    let (pa, pb) = (peak(ta), peak(tb));
    let phase: Vec<f64> = (0..n).map(|i| i as f64 / n as f64).collect();
    for (file, torque) in [("compare_angles.png", false), ("compare_torques.png", true)] {
        let mut panels = Vec::new();
        for leg in Leg::ALL {
            let mut traces = Vec::new();
            for (k, r) in rows
                .iter()
                .filter(|r| r.leg == leg && r.summed_side.is_none())
                .enumerate()
            {
                for (side, (t, p)) in [(ta, pa), (tb, pb)].into_iter().enumerate() {
                    if let Some(d) = t
                        .iter()
                        .find(|d| d.leg == leg && format!("{:?}", d.kind) == r.dof)
                    {
                        let v = if torque { &d.torque } else { &d.angle };
                        let v = planner::analysis::resample_periodic(v, n);
                        let values = v
                            .iter()
                            .map(|x| if torque { x / p } else { x.to_degrees() })
                            .collect();
                        let label = format!("{} {}", r.dof, if side == 0 { "A" } else { "B" });
                        traces.push(Trace {
                            label,
                            values,
                            dashed: side == 1,
                            colour: k,
                        });
                    }
                }
            }
            let what = if torque { "torque / peak" } else { "angle" };
            panels.push(Panel {
                leg,
                title: format!("{} {what}: A solid, B dashed", leg.name()),
                traces,
                stance: vec![],
            });
        }
        let y = if torque {
            "torque / plan's peak |torque|"
        } else {
            "angle (deg)"
        };
        replace(out, file, |p| {
            Ok(plot_leg_panels(
                p,
                &panels,
                &phase,
                "phase of the step cycle",
                y,
            )?)
        })?;
    }
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
        let plan = planner::plan::plan(&model, &p)
            .with_context(|| format!("planning with swing {sw} s"))?;
        let mut inputs = plan_inputs(&plan);
        let peak_of = |inputs: &[planner::dynamics::SliceInput]| -> Result<f64> {
            let c = solve_cycle(&model, inputs, &DynamicsOptions::default())
                .with_context(|| format!("dynamics with swing {sw} s"))?;
            Ok(c.slices
                .iter()
                .flat_map(|s| s.torque.iter())
                .fold(0.0f64, |m, t| m.max(t.abs())))
        };
        let peak_torque = peak_of(&inputs)?;
        // The same motion without gravity (and without springs' static share): inertia only.
        for i in &mut inputs {
            i.gravity = nalgebra::Vector3::zeros();
        }
        let peak_inertial_torque = peak_of(&inputs)?;
        points.push(SweepPoint {
            period: plan.period_s,
            peak_torque,
            peak_inertial_torque,
        });
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
            [p.period, p.peak_torque, p.peak_inertial_torque, share].map(|v| format!("{v:.6e}")),
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

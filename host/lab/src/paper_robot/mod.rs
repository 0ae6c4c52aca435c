//! The paper's robot experiments (figures 5 to 7) on the physics robot. Figure 5: forward
//! walking planned at step periods of 1, 2 and 4 s; figure 6: forward against backward at 2 s;
//! figure 7: up a 15 degree incline against flat ground at 2 s. Each run's per-slice load
//! statistics go to `phase_torques.csv` ([`csv_io`]), the plots (one per leg pair for figure 5)
//! are drawn from it, and the physics section of docs/validation.md is rendered from it
//! ([`block`]).

pub mod block;
pub mod csv_io;
pub mod experiment;
pub mod metrics;

use std::path::Path;

use board::files::write_atomically;
use planner::terrain::Ground;
use protocol::Direction;

use crate::bail;
use crate::error::{Context, Result};
use experiment::{Experiment, PhaseRow};

/// The step periods a quick run may be planned at, s.
pub const PERIODS_S: std::ops::RangeInclusive<f64> = 0.5..=10.0;

/// The runs of the full set (paper: 10 steps on flat ground, 5 on the incline; one more each
/// here, the first being left out) or of `--quick`.
pub fn experiments(quick: bool, periods: &[f64]) -> Vec<Experiment> {
    if quick {
        let periods = if periods.is_empty() {
            &[2.0][..]
        } else {
            periods
        };
        return periods
            .iter()
            .map(|&t| Experiment::new(t, Direction::Forward, Ground::Flat, 3))
            .collect();
    }
    let mut v: Vec<Experiment> = [1.0, 2.0, 4.0]
        .into_iter()
        .map(|t| Experiment::new(t, Direction::Forward, Ground::Flat, 11))
        .collect();
    v.push(Experiment::new(2.0, Direction::Backward, Ground::Flat, 11));
    v.push(Experiment::new(
        2.0,
        Direction::Forward,
        Ground::Incline { angle_deg: 15.0 },
        6,
    ));
    v
}

/// What [`run_all`] found: the load rows as read back from `phase_torques.csv` (everything
/// downstream uses the file's numbers, see [`csv_io`]) and per run its simulated gauges against
/// the predicted strain (written as `out/strain/NAME/strain_vs_plan.{csv,png}`).
#[derive(Debug, Clone)]
pub struct Runs {
    pub rows: Vec<PhaseRow>,
    pub strain: Vec<(String, Vec<crate::walk_fits::Fit>)>,
}

/// Runs `runs` one after the other (announcing each through `on_run(index, run)`), keeping each
/// recording as `out/runs/NAME/telemetry.csv` with `telemetry`; writes `phase_torques.csv`, the
/// plots and per run `strain/NAME/strain_vs_plan.{csv,png}` into `out`. `stop` ends the current
/// walk early.
pub fn run_all(
    out: &Path,
    runs: &[Experiment],
    telemetry: bool,
    mut on_run: impl FnMut(usize, &Experiment),
    stop: impl Fn() -> bool,
) -> Result<Runs> {
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    if let Some(e) = runs
        .iter()
        .find(|e| !(e.period_s.is_finite() && PERIODS_S.contains(&e.period_s)))
    {
        bail!(
            "periods: {} s is not a step period in 0.5..=10 s",
            e.period_s
        );
    }
    let mut rows = Vec::new();
    let mut strain = Vec::new();
    for (i, e) in runs.iter().enumerate() {
        on_run(i, e);
        let dir = out.join("runs").join(&e.name);
        let (r, fits) = experiment::run(e, telemetry.then_some(dir.as_path()), &stop)?;
        rows.extend(r);
        if fits.iter().any(|f| f.samples > 0) {
            let sdir = out.join("strain").join(&e.name);
            std::fs::create_dir_all(&sdir)
                .with_context(|| format!("creating {}", sdir.display()))?;
            let plan = planner::plan::plan(
                &planner::model::builtin("drosophibot2")?,
                &experiment::plan_params(e)?,
            )
            .with_context(|| format!("{}: planning the step", e.name))?;
            crate::strain_walk::write_strain_files(&sdir, &plan, &fits)?;
        }
        strain.push((e.name.clone(), fits));
    }
    write_atomically(&out.join(csv_io::FILE), |p| Ok(csv_io::write(p, &rows)?))?;
    let rows = csv_io::read(&out.join(csv_io::FILE))?;
    plots(out, &rows)?;
    Ok(Runs { rows, strain })
}

/// `text` with its physics section replaced by `section` (markers included).
pub fn splice(text: &str, section: &str) -> Result<String> {
    match (text.find(block::BEGIN), text.find(block::END)) {
        (Some(b), Some(e)) if b < e => {
            let end = e + block::END.len();
            let end = if text[end..].starts_with('\n') {
                end + 1
            } else {
                end
            };
            Ok(format!("{}{}{}", &text[..b], section, &text[end..]))
        }
        _ => bail!(
            "no `{}` ... `{}` pair, in that order",
            block::BEGIN,
            block::END
        ),
    }
}

/// Figure 5 per leg pair (the left leg, as the paper shows one leg per pair), figures 6 and 7
/// with all three left legs.
pub fn plots(out: &Path, rows: &[PhaseRow]) -> Result<()> {
    let present = |e: &str| rows.iter().any(|r| r.experiment == e);
    let draw = |file: &str, title: &str, legs: &[&str], runs: &[(&str, &str)]| -> Result<()> {
        let runs: Vec<(&str, &str)> = runs.iter().copied().filter(|(e, _)| present(e)).collect();
        if runs.is_empty() {
            return Ok(());
        }
        let mut joints: Vec<String> = Vec::new();
        for r in rows.iter().filter(|r| r.experiment == runs[0].0) {
            if legs.iter().any(|l| r.joint.starts_with(l)) && !joints.contains(&r.joint) {
                joints.push(r.joint.clone());
            }
        }
        let column = |e: &str, j: &str, f: fn(&PhaseRow) -> f64| -> Vec<f64> {
            rows.iter()
                .filter(|r| r.experiment == e && r.joint == j)
                .map(f)
                .collect()
        };
        let stance: Vec<Vec<bool>> = joints
            .iter()
            .map(|j| {
                rows.iter()
                    .filter(|r| r.experiment == runs[0].0 && r.joint == *j)
                    .map(|r| r.stance)
                    .collect()
            })
            .collect();
        let series: Vec<report::paper_robot::Run> = runs
            .iter()
            .map(|(e, label)| report::paper_robot::Run {
                label: (*label).to_owned(),
                planned: joints
                    .iter()
                    .map(|j| column(e, j, |r| r.planned_nm))
                    .collect(),
                mean: joints.iter().map(|j| column(e, j, |r| r.mean_nm)).collect(),
                sd: joints.iter().map(|j| column(e, j, |r| r.sd_nm)).collect(),
            })
            .collect();
        Ok(write_atomically(&out.join(file), |p| {
            Ok(
                report::paper_robot::plot_runs(p, title, &joints, &stance, &series)
                    .map_err(|e| format!("plotting {file}: {e}"))?,
            )
        })?)
    };
    let fwd = [
        ("forward-1s", "1 s"),
        ("forward-2s", "2 s"),
        ("forward-4s", "4 s"),
    ];
    for (leg, pair) in [("LF", "front"), ("LM", "middle"), ("LH", "hind")] {
        draw(
            &format!("fig5-{pair}.png"),
            &format!(
                "Figure 5 in simulation, {leg} ({pair} leg): torque from servo load at step periods 1, 2, 4 s, beside the planner's"
            ),
            &[leg],
            &fwd,
        )?;
    }
    draw(
        "fig6.png",
        "Figure 6 in simulation: forward vs backward at 2 s, each beside its own plan, LF, LM, LH",
        &["LF", "LM", "LH"],
        &[("forward-2s", "forward"), ("backward-2s", "backward")],
    )?;
    draw(
        "fig7.png",
        "Figure 7 in simulation: 15 deg incline vs flat at 2 s, LF, LM, LH",
        &["LF", "LM", "LH"],
        &[
            ("forward-2s", "flat"),
            ("forward-incline15-2s", "incline 15 deg"),
        ],
    )?;
    Ok(())
}

//! `dbot paper-robot`: the paper's robot experiments (figures 5 to 7) on the physics robot.
//! Figure 5: forward walking planned at step periods of 1, 2 and 4 s; figure 6: forward against
//! backward at 2 s; figure 7: up a 15 degree incline against flat ground at 2 s. Each run's
//! per-slice load statistics go to `phase_torques.csv`, the plots (one per leg pair for figure 5)
//! are drawn from it, and the physics section of docs/validation.md is rendered from it
//! (`--from DIR --write/--check FILE`).

mod block;
mod csv_io;
mod experiment;
mod metrics;

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use protocol::Direction;

use crate::common::output::replace;
use experiment::{Experiment, PhaseRow};

/// The paper's figures 5 to 7 on the physics robot (MuJoCo body, firmware in the loop).
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot paper-robot --out out/paper-robot            # all runs (about 110 s simulated)
  dbot paper-robot --out /tmp/q --quick             # forward at 2 s, 3 steps
  dbot paper-robot --out /tmp/q --quick --periods 1,4   # forward at 1 s and at 4 s
  cargo run --release --bin dbot -- paper-robot --out docs/paper-robot
  dbot paper-robot --from docs/paper-robot --write docs/validation.md
  dbot paper-robot --from docs/paper-robot --check docs/validation.md")]
pub struct Args {
    /// Output directory of a run: phase_torques.csv and the plots.
    #[arg(long, conflicts_with = "from")]
    out: Option<PathBuf>,
    /// Forward runs only, 3 steps each (2 averaged), at a 2 s period or at --periods.
    #[arg(long)]
    quick: bool,
    /// Step periods (s) of the quick run's forward walks, e.g. `1,4`.
    #[arg(long, value_delimiter = ',', requires = "quick")]
    periods: Vec<f64>,
    /// Keep each run's recording as runs/NAME/telemetry.csv under --out.
    #[arg(long)]
    telemetry: bool,
    /// Render the physics section from DIR/phase_torques.csv instead of running (with --write or
    /// --check).
    #[arg(long)]
    from: Option<PathBuf>,
    /// Put the rendered section between the physics markers of this file.
    #[arg(long, group = "doc")]
    write: Option<PathBuf>,
    /// Fail if the physics section of this file differs from the rendered one.
    #[arg(long, group = "doc")]
    check: Option<PathBuf>,
}

/// The runs of the full set (paper: 10 steps on flat ground, 5 on the incline; one more each
/// here, the first being left out) or of `--quick`.
fn experiments(quick: bool, periods: &[f64]) -> Vec<Experiment> {
    if quick {
        let periods = if periods.is_empty() {
            &[2.0][..]
        } else {
            periods
        };
        return periods
            .iter()
            .map(|&t| Experiment::new(t, Direction::Forward, "flat", 3))
            .collect();
    }
    let mut v: Vec<Experiment> = [1.0, 2.0, 4.0]
        .into_iter()
        .map(|t| Experiment::new(t, Direction::Forward, "flat", 11))
        .collect();
    v.push(Experiment::new(2.0, Direction::Backward, "flat", 11));
    v.push(Experiment::new(2.0, Direction::Forward, "incline:15", 6));
    v
}

impl Args {
    pub fn run(self) -> Result<()> {
        let rows = match (&self.out, &self.from) {
            (Some(out), None) => self.simulate(out)?,
            (None, Some(dir)) => csv_io::read(&dir.join(csv_io::FILE))?,
            _ => bail!("give --out DIR (run the experiments) or --from DIR (use their CSV)"),
        };
        let section = block::render(&rows);
        if let Some(path) = &self.write {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("reading {}", path.display()))?;
            let new = splice(&text, &section).with_context(|| path.display().to_string())?;
            crate::common::output::replace_file(path, |p| Ok(std::fs::write(p, &new)?))?;
            println!("{}: physics section written", path.display());
        }
        if let Some(path) = &self.check {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("reading {}", path.display()))?;
            if splice(&text, &section).with_context(|| path.display().to_string())? != text {
                bail!(
                    "{}: the physics section has drifted from {}: run `dbot paper-robot --from {} --write {}`",
                    path.display(),
                    csv_io::FILE,
                    self.from
                        .as_ref()
                        .or(self.out.as_ref())
                        .map_or(String::new(), |p| p.display().to_string()),
                    path.display()
                );
            }
            println!("{}: physics section matches", path.display());
        }
        Ok(())
    }

    fn simulate(&self, out: &Path) -> Result<Vec<PhaseRow>> {
        crate::common::interrupt::catch()?;
        std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
        if let Some(t) = self
            .periods
            .iter()
            .find(|t| !(t.is_finite() && (0.5..=10.0).contains(*t)))
        {
            bail!("--periods: {t} s is not a step period in 0.5..=10 s");
        }
        let runs = experiments(self.quick, &self.periods);
        let mut rows = Vec::new();
        for (i, e) in runs.iter().enumerate() {
            println!(
                "[{}/{}] {}: period {} s, {} steps on {}",
                i + 1,
                runs.len(),
                e.name,
                e.period_s,
                e.steps,
                e.terrain
            );
            let dir = out.join("runs").join(&e.name);
            rows.extend(experiment::run(e, self.telemetry.then_some(dir.as_path()))?);
        }
        replace(out, csv_io::FILE, |p| csv_io::write(p, &rows))?;
        // Everything downstream uses the file's numbers (see csv_io).
        let rows = csv_io::read(&out.join(csv_io::FILE))?;
        plots(out, &rows)?;
        println!("wrote {} and plots in {}", csv_io::FILE, out.display());
        for line in summary(&rows) {
            println!("  {line}");
        }
        Ok(rows)
    }
}

/// `text` with its physics section replaced by `section` (markers included).
fn splice(text: &str, section: &str) -> Result<String> {
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

/// One line per experiment and group: load against plan (RMS, R^2) and the spread over steps.
fn summary(rows: &[PhaseRow]) -> Vec<String> {
    let mut names: Vec<&str> = Vec::new();
    for r in rows {
        if !names.contains(&r.experiment.as_str()) {
            names.push(&r.experiment);
        }
    }
    let mut out = Vec::new();
    for e in names {
        for g in metrics::Group::all() {
            out.push(format!(
                "{e:<22} {:<14} load - planned RMS {:.3} N m, R^2 {}, SD over steps {:.3} N m",
                g.name(),
                metrics::load_vs_plan(rows, e, g).unwrap_or(f64::NAN),
                metrics::r_squared(rows, e, g).map_or("-".into(), |v| format!("{v:.2}")),
                metrics::spread(rows, e, g).unwrap_or(f64::NAN),
            ));
        }
    }
    out
}

/// Figure 5 per leg pair (the left leg, as the paper shows one leg per pair), figures 6 and 7
/// with all three left legs.
fn plots(out: &Path, rows: &[PhaseRow]) -> Result<()> {
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
        replace(out, file, |p| {
            report::paper_robot::plot_runs(p, title, &joints, &stance, &series)
                .map_err(|e| anyhow::anyhow!("plotting {file}: {e}"))
        })
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

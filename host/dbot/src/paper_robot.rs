//! `dbot paper-robot`: the paper's robot experiments (figures 5 to 7) on the physics robot
//! (`lab::paper_robot`: the runs, `phase_torques.csv`, the plots and the physics section of
//! docs/validation.md, `--from DIR --write/--check FILE`). This file parses, announces the runs
//! and prints their summary.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use lab::paper_robot::experiment::PhaseRow;
use lab::paper_robot::{block, csv_io, experiments, metrics, run_all, splice};

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
        let runs = experiments(self.quick, &self.periods);
        let done = run_all(
            out,
            &runs,
            self.telemetry,
            |i, e| {
                println!(
                    "[{}/{}] {}: period {} s, {} steps on {}",
                    i + 1,
                    runs.len(),
                    e.name,
                    e.period_s,
                    e.steps,
                    e.terrain
                )
            },
            crate::common::interrupt::requested,
        )?;
        let rows = done.rows;
        println!("wrote {} and plots in {}", csv_io::FILE, out.display());
        for line in summary(&rows) {
            println!("  {line}");
        }
        println!(
            "simulated gauges vs predicted strain (by the slice the firmware played; {}/strain/RUN/strain_vs_plan.png, .csv):",
            out.display()
        );
        for (name, fits) in &done.strain {
            println!("  {}", lab::strain_walk::summary_line(name, fits));
        }
        Ok(rows)
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
                metrics::load_r2(rows, e, g).map_or("-".into(), |v| format!("{v:.2}")),
                metrics::spread(rows, e, g).unwrap_or(f64::NAN),
            ));
        }
    }
    out
}

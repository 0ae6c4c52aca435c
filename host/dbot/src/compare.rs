//! `dbot compare`: R-squared of angle and torque regressions per common DoF of two plans
//! (tables S2 to S8 of the paper) with overlaid plots, or a speed sweep over swing durations
//! (`lab::plan_comparison`), or the paper's comparison (`lab::paper_comparison`). This file
//! parses, shows the sweep's progress and prints the tables.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};

/// Compare two plans DoF by DoF, or sweep the swing duration of one model.
///
/// With two plan directories (written by `dbot plan`, with torques) or trial folders (written by
/// `dbot record`: the measured angles and the load torques, an ESTIMATE, averaged per slice over
/// steps 1 to the last whole one), in any mix: per common DoF the R-squared of a linear regression
/// of the angles and of the torques, plus ThC2+CTr summed where one organism elevates with both;
/// writes compare.csv, compare_angles.png, compare_torques.png. A trial against its own plan says
/// how well the robot followed it.
/// With --swing S1,S2,..: plans --model at each swing duration and reports how the peak torque
/// and its inertial part scale with the step period (quasi-static or inertial regime).
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot compare out/walk out/fly-ball                  # writes out/compare/compare.csv and plots
  dbot compare out/walk 'trials/2026-12-02 09_30_00'   # a trial against the plan it walked
  dbot compare --swing 0.4,0.8,1.6 --out out/sweep    # the speed sweep of Drosophibot II
  dbot compare --strain \"trials/2026-12-02 14_08_00\" out/walk   # recorded strain vs the plan's")]
pub struct Args {
    /// Plan directories or trial folders A and B (from `dbot plan` / `dbot demo`, with torques,
    /// or `dbot record`).
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
    /// A trial recorded with `dbot record --strain`: its strain against the prediction of the one
    /// plan directory given, per gauge (R^2 over the step phase, a fitted gain in counts per
    /// microstrain, the RMS in microstrain through the plan model's calibration or the ESTIMATE
    /// gain, saying which); writes strain_gains.csv to --out.
    #[arg(long, value_name = "TRIAL")]
    strain: Option<PathBuf>,
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
            let c = lab::paper_comparison::run_paper(&self.out, self.slices)?;
            println!("{}", c.markdown);
            println!(
                "wrote tables.md tables.csv and per-case plots to {}",
                self.out.display()
            );
            return Ok(());
        }
        if let Some(trial) = &self.strain {
            let [plan] = self.plans.as_slice() else {
                bail!("--strain TRIAL compares with one plan directory: give exactly one");
            };
            return compare_strain(trial, plan, &self.out);
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

fn compare_dirs(a: &Path, b: &Path, out: &Path) -> Result<()> {
    let rows = lab::plan_comparison::compare_dirs(a, b, out)?;
    print!("{}", lab::plan_comparison::table(&rows));
    println!(
        "wrote compare.csv compare_angles.png compare_torques.png to {}",
        out.display()
    );
    Ok(())
}

fn compare_strain(trial: &Path, plan: &Path, out: &Path) -> Result<()> {
    let fits = lab::strain_compare::compare_trial(trial, plan)?;
    print!("{}", lab::strain_compare::table(&fits));
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let path = out.join(lab::strain_compare::GAINS_CSV);
    std::fs::write(&path, lab::strain_compare::gains_csv(&fits))
        .with_context(|| format!("writing {}", path.display()))?;
    println!("wrote {}", path.display());
    Ok(())
}

fn sweep(model: &str, swings: &[f64], out: &Path) -> Result<()> {
    let model = crate::common::model_spec::load_model(model)?;
    let bar = indicatif::ProgressBar::new(swings.len() as u64);
    let swept = lab::plan_comparison::sweep(&model, swings, out, || bar.inc(1));
    bar.finish_and_clear();
    let (points, regime) = swept?;
    print!(
        "{}",
        lab::plan_comparison::sweep_table(&points, regime.as_ref())
    );
    println!("wrote sweep.csv to {}", out.display());
    Ok(())
}

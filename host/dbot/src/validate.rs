//! `dbot validate`: regenerates docs/validation.md's run results (`lab::validation`: the
//! generated blocks, the plots, the comparison as ratios of the timings). This file parses and
//! says what changed or drifted.

use std::path::PathBuf;

use anyhow::{Result, bail};
use lab::validation::blocks::Part;

/// Regenerate (or check) the run results and plots of docs/validation.md.
///
/// Plans and solves the built-in models (table 1 parameters), the servo feasibility of the default
/// and the original swing, the IK's continuity, the 15 degree incline, the resting posture, the
/// speed sweep, the timings and the paper's comparison (`dbot compare --paper`, 50 slices per step
/// to keep the check quick), fills the document's generated blocks and writes its plots to
/// `validation/` beside it.
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot validate --check docs/validation.md     # fails naming every block or plot that drifted
  dbot validate --check docs/validation.md --part paper   # one part only (quicker)
  cargo run --release --bin dbot -- validate --write docs/validation.md   # timings from a release build")]
pub struct Args {
    /// Fill the generated blocks of this file in place and write its plots.
    #[arg(long, group = "mode")]
    write: Option<PathBuf>,
    /// Fail (listing the blocks and plots) if this file differs from a fresh run.
    #[arg(long, group = "mode")]
    check: Option<PathBuf>,
    /// Keep the comparison's plots (`dbot compare --paper` layout) in this directory.
    #[arg(long)]
    plots: Option<PathBuf>,
    /// Only this part's blocks and plots (the others are left as they are): plans, paper, sweep,
    /// strain, steering, timing or trials.
    #[arg(long, value_parser = part_name)]
    part: Option<Part>,
}

fn part_name(name: &str) -> Result<Part, String> {
    Part::from_name(name).ok_or_else(|| {
        let names: Vec<&str> = Part::ALL.iter().map(|p| p.name()).collect();
        format!("no part `{name}`: one of {}", names.join(", "))
    })
}

impl Args {
    pub fn run(self) -> Result<()> {
        let (path, write) = match (&self.write, &self.check) {
            (Some(p), None) => (p, true),
            (None, Some(p)) => (p, false),
            _ => bail!("give --write FILE or --check FILE"),
        };
        let done = lab::validation::update(path, write, self.plots.as_deref(), self.part)?;
        let what = format!("{} generated blocks and {} plots", done.blocks, done.plots);
        if write {
            println!("{}: {what} ({} changed)", path.display(), done.stale.len());
        } else if !done.stale.is_empty() {
            bail!(
                "{} has drifted from the code in block(s) {}: run `dbot validate --write {}`",
                path.display(),
                done.stale.join(", "),
                path.display()
            );
        } else {
            println!("{}: all {what} match", path.display());
        }
        Ok(())
    }
}

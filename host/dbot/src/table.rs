//! `dbot table`: turn a plan directory (from `dbot plan` or `dbot demo`, with torques) into the
//! step table the board plays back.

use std::path::PathBuf;

use anyhow::Result;
use planner::plan_dir;

use crate::common::output::replace_file;

/// Build the board's step table from a plan directory.
///
/// The table holds the planned angle (rad) and modelled actuator torque (N m) of every servo per
/// slice, stance flags, step period and duty; the firmware adds the torque bias (torque / servo
/// stiffness) to each command. `dbot upload --plan DIR` builds the same bytes.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Plan directory written by `dbot plan` or `dbot demo` (plan.json, model.toml, joints.csv
    /// with torque_nm, feet.csv).
    #[arg(long)]
    plan: PathBuf,
    /// Output file for the table bytes.
    #[arg(long)]
    out: PathBuf,
    /// Gait name stored in the table (at most 16 bytes); default: the plan's (plan.json's
    /// `table_name` from `dbot plan --name`, else the plan directory's name).
    #[arg(long)]
    name: Option<String>,
}

impl Args {
    pub fn run(self) -> Result<()> {
        let plan = plan_dir::read(&self.plan)?;
        let bytes = plan.step_table(self.name.as_deref())?;
        replace_file(&self.out, |p| Ok(std::fs::write(p, &bytes)?))?;
        println!(
            "{}: {} slices, period {:.3} s, {} bytes to {}",
            plan.model.name,
            plan.json.slices,
            plan.json.period_s,
            bytes.len(),
            self.out.display()
        );
        Ok(())
    }
}

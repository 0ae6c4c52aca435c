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
/// stiffness) to each command. The model is the plan's (plan.json); a setup file naming another
/// model gets a warning, since the table would not fit that robot. `dbot upload --plan DIR` builds
/// the same bytes.
#[derive(Debug, clap::Args)]
#[command(after_help = "Example:
  dbot table --plan out/walk --out walk.dbgt          # then: dbot upload --table walk.dbgt --slot 1")]
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
    #[command(flatten)]
    feasibility: crate::feasibility_args::FeasibilityArgs,
    /// Robot setup file (TOML) whose `model` the plan's is checked against. Default:
    /// $DBOT_CONFIG, ./dbot.toml, ~/.config/dbot/config.toml.
    #[arg(long)]
    config: Option<PathBuf>,
}

impl Args {
    pub fn run(self) -> Result<()> {
        let plan = plan_dir::read(&self.plan)?;
        let dir = &self.plan;
        let (setup, setup_path) = board::setup_file::RobotConfig::find(self.config.as_deref())?;
        if let (Some(want), Some(file)) = (&setup.model, &setup_path)
            && *want != plan.json.model_source
            && *want != plan.model.name
        {
            eprintln!(
                "warning: {} was planned for model {} but {} names model {want}: this table fits {}",
                dir.display(),
                plan.model.name,
                file.display(),
                plan.model.name
            );
        }
        let table = board::rules::build::plan_dir_table(
            &plan,
            self.name.as_deref(),
            self.feasibility.overrides(),
        )?;
        crate::feasibility_args::warn(table.warning());
        let bytes = table.bytes();
        replace_file(&self.out, |p| Ok(std::fs::write(p, bytes)?))?;
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

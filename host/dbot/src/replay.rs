//! `dbot replay`: a trial's goals played on the physics robot, per joint R^2 and RMS (`lab::replay`).
use crate::args::setup::ModelArgs;

/// Replay a recorded trial's goals on the physics robot with a model's servo dynamics and print
/// per joint R^2 and RMS of position, velocity and load (the sim-to-real figure of merit).
#[derive(Debug, clap::Args)]
#[command(after_help = "Example:\n  dbot replay out/trials/walk --model fitted.toml")]
pub struct Args {
    /// The trial folder.
    trial: std::path::PathBuf,
    #[command(flatten)]
    model: ModelArgs,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        let model = crate::common::model_spec::load_model(&self.model.spec()?)?;
        Ok(print!("{}", lab::replay::replay_trial(&self.trial, &model)?.table()))
    }
}

//! `dbot replay`: a trial replayed on the physics robot, per joint R^2 and RMS (`lab::replay`).

/// Replay a trial's goals on the physics robot: per joint R^2 and RMS of position, velocity, load.
#[derive(Debug, clap::Args)]
#[command(after_help = "Example:\n  dbot replay out/trials/walk --model fitted.toml")]
pub struct Args {
    /// The trial folder.
    trial: std::path::PathBuf,
    #[command(flatten)]
    model: crate::args::setup::ModelArgs,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        let model = crate::common::model_spec::load_model(&self.model.spec()?)?;
        let replay = lab::replay::replay_trial(&self.trial, &model)?;
        print!("{}", replay.table());
        Ok(())
    }
}

//! `dbot identify`: the servo dynamics and the ground friction fitted to recorded trials
//! (`lab::identify`).

/// Fit the model's servo dynamics to suspended excitation trials, then the ground's friction
/// (`foot_friction`) to the trials that walked, when their feet slip (docs/identification.md):
/// each trial's goals replayed on the physics robot; writes the fitted model and FITTED-report/.
#[derive(Debug, clap::Args)]
#[command(after_help = "Example:
  dbot identify out/trials/sus-CTr out/trials/sus-FTi --model drosophibot2 --out fitted.toml
  dbot identify out/trials/sus-* --model drosophibot2 --out fitted.toml --refine-replays 600
  dbot identify out/trials/walk-floor --model fitted.toml --out fitted-floor.toml")]
pub struct Args {
    /// Trial folders: `dbot record` of `dbot excite --kind suspended`'s sus-* tables (the servo
    /// dynamics), and walks on the ground (its friction; walks on one substrate).
    #[arg(required = true)]
    trials: Vec<std::path::PathBuf>,
    /// The fitted model file to write (its folder is made if missing).
    #[arg(long)]
    out: std::path::PathBuf,
    #[command(flatten)]
    model: crate::args::setup::ModelArgs,
    /// After Levenberg-Marquardt, refine each identified joint by Nelder-Mead on its own cost
    /// with at most this many replays (0: no refinement; on the one-leg stand-in 300 with short
    /// tables, 600 with the full-length ones brought every field within 10 %,
    /// docs/identification.md).
    #[arg(long, default_value_t = 0)]
    refine_replays: usize,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        let model = crate::common::model_spec::load_model(&self.model.spec()?)?;
        let options = lab::identify::IdentifyOptions {
            refine_replays_per_joint: self.refine_replays,
            ..Default::default()
        };
        lab::identify::prepare_out(&self.out)?;
        let id = lab::identify::identify_trials(&self.trials, &model, &options)?;
        print!("{}", lab::identify::write_outputs(&id, &self.out)?);
        Ok(())
    }
}

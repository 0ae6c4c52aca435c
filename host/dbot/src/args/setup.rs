//! `--model` and `--config` of the planning commands (`plan`, `compare`, `table`): the model comes
//! from the flag, else the setup file's `model`, else the built-in Drosophibot II.

use std::path::PathBuf;

use board::setup_file::RobotConfig;

/// The built-in model used when neither `--model` nor the setup file names one.
pub const DEFAULT_MODEL: &str = "drosophibot2";

/// Which robot model to plan for.
#[derive(Debug, Clone, clap::Args)]
pub struct ModelArgs {
    /// Built-in model name (drosophibot2, scale-drosophila), a .toml model or an .aproj file.
    /// Default: the setup file's `model`, else drosophibot2.
    #[arg(long)]
    pub model: Option<String>,
    /// Robot setup file (TOML) whose `model` is used without --model. Default: $DBOT_CONFIG,
    /// ./dbot.toml, ~/.config/dbot/config.toml.
    #[arg(long)]
    pub config: Option<PathBuf>,
}

impl ModelArgs {
    /// The model spec: flag, setup file (its paths relative to the file), built-in default.
    pub fn spec(&self) -> anyhow::Result<String> {
        if let Some(m) = &self.model {
            return Ok(m.clone());
        }
        let (setup, _) = RobotConfig::find(self.config.as_deref())?;
        Ok(setup.model.unwrap_or_else(|| DEFAULT_MODEL.to_owned()))
    }
}

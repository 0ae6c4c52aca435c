//! `dbot calibrate`: calibrated readings from a standing trial (`lab::calibrate`).

/// Fit the readings to a standing trial (docs/identification.md): per servo joint the Present Load
/// gain and offset, per gauge its counts per microstrain, against the plan's prediction or the
/// trial replayed on the model's body; writes the calibration file. Below R^2 0.8: ESTIMATE kept.
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot calibrate out/trials/stand --model drosophibot2 --out cal.toml
  dbot calibrate out/trials/stand --model fitted.toml --against replay --out cal.toml")]
pub struct Args {
    /// The trial folder (`dbot record --strain` of `dbot excite --kind standing`'s table).
    trial: std::path::PathBuf,
    /// The calibration file to write (TOML).
    #[arg(long)]
    out: std::path::PathBuf,
    /// `plan` (the plan's static prediction) or `replay` (the trial replayed on the model's
    /// body: give the model `dbot identify` fitted); a bad word refused in Python's words.
    #[arg(long, default_value = "plan")]
    against: String,
    #[command(flatten)]
    model: crate::args::setup::ModelArgs,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        let against = lab::calibrate::Against::parse(&self.against)?;
        let model = crate::common::model_spec::load_model(&self.model.spec()?)?;
        let cal = lab::calibrate::calibrate_trial(&self.trial, &model, against)?;
        lab::calibrate::write(&cal, &model, &self.out)?;
        println!("{}wrote {}", cal.table(), self.out.display());
        Ok(())
    }
}

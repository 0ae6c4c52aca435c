//! `dbot calibrate`: calibrated readings from a standing trial (`lab::calibrate`).

/// Fit the readings to a standing trial (docs/identification.md, "Calibrated readings"): per
/// servo joint the Present Load gain and offset against the predicted torque, per strain gauge
/// its counts per microstrain against the predicted strain (the plan's, or with `--against
/// replay` the trial replayed on the model's body); writes the calibration file a model file
/// names (`calibration = "FILE"`). Fits below R^2 0.8 keep their ESTIMATE.
#[derive(Debug, clap::Args)]
#[command(
    after_help = "Examples:\n  dbot calibrate out/trials/stand --model drosophibot2 --out cal.toml\n  dbot calibrate out/trials/stand --model fitted.toml --against replay --out cal.toml"
)]
pub struct Args {
    /// The trial folder (`dbot record --strain` of `dbot excite --kind standing`'s table).
    trial: std::path::PathBuf,
    /// The calibration file to write (TOML).
    #[arg(long)]
    out: std::path::PathBuf,
    /// What the readings are fitted against: `plan`, the plan's static prediction at the
    /// recorded goals; or `replay`, the trial replayed on the model's body (its servo dynamics
    /// and contacts: give the model `dbot identify` fitted).
    #[arg(long, default_value = "plan")]
    against: String,
    #[command(flatten)]
    model: crate::args::setup::ModelArgs,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        // Parsed here, not by clap, so a bad word fails as every refusal does, in Python's words.
        let against = lab::calibrate::Against::parse(&self.against)?;
        let model = crate::common::model_spec::load_model(&self.model.spec()?)?;
        let cal = lab::calibrate::calibrate_trial(&self.trial, &model, against)?;
        lab::calibrate::write(&cal, &model, &self.out)?;
        println!("{}wrote {}", cal.table(), self.out.display());
        Ok(())
    }
}

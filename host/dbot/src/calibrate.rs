//! `dbot calibrate`: calibrated readings from a standing trial (`lab::calibrate`).

/// Fit the readings to a standing trial (docs/identification.md, "Calibrated readings"): per
/// servo joint the Present Load gain and offset against the plan's predicted torque, per strain
/// gauge its counts per microstrain against the predicted strain; writes the calibration file a
/// model file names (`calibration = "FILE"`). Fits below R^2 0.8 keep their ESTIMATE.
#[derive(Debug, clap::Args)]
#[command(
    after_help = "Example:\n  dbot calibrate out/trials/stand --model drosophibot2 --out cal.toml"
)]
pub struct Args {
    /// The trial folder (`dbot record --strain` of `dbot excite --kind standing`'s table).
    trial: std::path::PathBuf,
    /// The calibration file to write (TOML).
    #[arg(long)]
    out: std::path::PathBuf,
    #[command(flatten)]
    model: crate::args::setup::ModelArgs,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        let model = crate::common::model_spec::load_model(&self.model.spec()?)?;
        let cal = lab::calibrate::calibrate_trial(&self.trial, &model)?;
        lab::calibrate::write(&cal, &model, &self.out)?;
        println!("{}wrote {}", cal.table(), self.out.display());
        Ok(())
    }
}

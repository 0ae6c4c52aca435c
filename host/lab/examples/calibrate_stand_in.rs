//! The calibration's figures in docs/identification.md ("Calibrated readings"): the reading
//! stand-in (`lab::identify::stand_in::reading_stand_in_model`: the default body, Present Load
//! read as 0.8 x torque + 0.05 N m, a strain board of gain 0.3 + 0.02 x column counts per
//! microstrain) records the full standing excitation (`dbot excite --kind standing`'s: 8 s
//! posture changes, 1 s holds) with strain as the trial folder OUT/stand (default
//! out/calibrate-stand-in), and model.toml, the built-in model naming `cal.toml`; then run
//! `dbot calibrate` and `dbot replay` as the document says. With `--full` the full stand-in
//! records it (`stand_in_model`: its servo dynamics too, friction, deadband and backlash), for
//! `dbot calibrate --against replay` on the model `dbot identify` fitted ("Against the replay").
//!
//! ```sh
//! cargo run -p lab --example calibrate_stand_in -- out/calibrate-stand-in
//! cargo run -p lab --example calibrate_stand_in -- out/calibrate-full-stand-in --full
//! ```

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let full = args.iter().any(|a| a == "--full");
    let out = args
        .iter()
        .find(|a| *a != "--full")
        .cloned()
        .unwrap_or_else(|| "out/calibrate-stand-in".into());
    let out = std::path::PathBuf::from(out);
    let default = planner::model::builtin("drosophibot2")?;
    let truth = if full {
        lab::identify::stand_in::stand_in_model(&default)
    } else {
        lab::identify::stand_in::reading_stand_in_model(&default)
    };
    let options = planner::excitation::ExcitationOptions::default();
    let trial = lab::identify::stand_in::write_standing_trial(&truth, &default, &options, &out)?;
    println!("standing trial with strain: {}", trial.display());
    let text = planner::model::to_toml_string(&default, "", &|_| String::new());
    let path = out.join("model.toml");
    std::fs::write(&path, format!("calibration = \"cal.toml\"\n{text}"))?;
    println!("the model naming cal.toml: {}", path.display());
    Ok(())
}

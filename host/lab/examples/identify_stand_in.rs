//! The stand-in robot's identification, the figures of docs/identification.md: the stand-in
//! (`lab::identify::stand_in`) records the suspended excitation of one leg's joints (short holds
//! and chirps) and a held-out walking step as trial folders under OUT (default
//! out/identify-stand-in), the stand-in's own model (stand-in.toml) and the model a lab
//! starts from (start.toml: the default with the I and D registers read from the servos); then run `dbot identify` and `dbot replay` on them as the document
//! says.
//!
//! ```sh
//! cargo run -p lab --example identify_stand_in -- out/identify-stand-in
//! cargo run -p lab --example identify_stand_in -- out/identify-full --full-length
//! ```
//!
//! The document's figure uses short tables (0.4 s holds, 4 s chirps); `--full-length` records
//! the tables a lab is told to record (the planner's defaults: 1 s holds, 20 s chirps).

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let full = args.iter().any(|a| a == "--full-length");
    let out = args
        .iter()
        .find(|a| !a.starts_with("--"))
        .cloned()
        .unwrap_or_else(|| "out/identify-stand-in".into());
    if let Some(bad) = args
        .iter()
        .find(|a| a.starts_with("--") && *a != "--full-length")
    {
        return Err(format!("unknown option {bad} (known: --full-length)").into());
    }
    let out = std::path::PathBuf::from(out);
    let default = planner::model::builtin("drosophibot2")?;
    let options = if full {
        planner::excitation::ExcitationOptions::default()
    } else {
        planner::excitation::ExcitationOptions {
            hold_s: 0.4,
            chirp_s: 4.0,
            chirp_taper_s: 0.3,
            ..Default::default()
        }
    };
    let joints: Vec<String> = ["LF_ThC1", "LF_ThC3", "LF_CTr", "LF_TrF1", "LF_FTi"]
        .map(String::from)
        .to_vec();
    let trials = lab::identify::stand_in::write_trials(&default, &options, &joints, &out)?;
    for t in &trials.suspended {
        println!("suspended: {}", t.display());
    }
    println!("held-out walk: {}", trials.walk.display());
    let truth = lab::identify::stand_in::stand_in_model(&default);
    let path = out.join("stand-in.toml");
    std::fs::write(
        &path,
        planner::model::to_toml_string(&truth, "The stand-in robot's model: the truth", &|_| {
            String::new()
        }),
    )?;
    println!("the stand-in's own model: {}", path.display());
    let start = lab::identify::stand_in::start_model(&default);
    let path = out.join("start.toml");
    let note = "drosophibot2 with the I and D gain registers read from the stand-in's servos";
    std::fs::write(
        &path,
        planner::model::to_toml_string(&start, note, &|_| String::new()),
    )?;
    println!("the model to start from: {}", path.display());
    Ok(())
}

//! docs/validation.md quotes run results; `dbot validate --check` regenerates them (built-in
//! models, feasibility, the incline error, the paper's comparison) and fails naming every generated
//! block of the document that differs, so the document cannot drift from the code. The paper's own
//! figures in the document are its statements, quoted beside ours (`planner::analysis::paper`).
//!
//! One test per part of the run results (`--part`, `lab::validation::blocks::Part`), so that nextest
//! runs them side by side; together they check every block and plot.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn validate(doc: &Path, part: &str) -> Output {
    Command::new(env!("CARGO_BIN_EXE_dbot"))
        .args(["validate", "--check", doc.to_str().unwrap(), "--part", part])
        .output()
        .unwrap()
}

/// The part's blocks and plots in docs/validation.md match a fresh run.
fn part_matches(part: &str) {
    let o = validate(&repo().join("docs/validation.md"), part);
    assert!(
        o.status.success(),
        "part `{part}` (run `dbot validate --write docs/validation.md` if the code changed on purpose):\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains(" match"), "{out}");
}

#[test]
fn the_plans_part_matches_a_fresh_run_and_drift_is_named() {
    // The document with one figure changed (the old drift, 49.48 N for the robot's 49.06 N
    // weight) must fail naming that block only, so every other block of the part matches.
    let text = std::fs::read_to_string(repo().join("docs/validation.md")).unwrap();
    assert!(
        text.contains("weight 49.06 N"),
        "docs/validation.md no longer quotes the robot's weight as 49.06 N"
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("validation.md");
    std::fs::write(&path, text.replacen("weight 49.06 N", "weight 49.48 N", 1)).unwrap();
    // The plots beside it, one of them missing: named as drifted too.
    std::fs::create_dir_all(dir.path().join("validation")).unwrap();
    for f in std::fs::read_dir(repo().join("docs/validation")).unwrap() {
        let f = f.unwrap().path();
        let name = f.file_name().unwrap().to_owned();
        if name != "fly_flat_torques.png" {
            std::fs::copy(&f, dir.path().join("validation").join(name)).unwrap();
        }
    }
    let o = validate(&path, "plans");
    let e = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(!o.status.success());
    assert!(
        e.contains(
            "has drifted from the code in block(s) weight, validation/fly_flat_torques.png:"
        ),
        "expected only the `weight` block and the missing plot to differ (run `dbot validate --write docs/validation.md` if the code changed on purpose):\n{e}"
    );
}

#[test]
fn the_paper_part_matches_a_fresh_run() {
    part_matches("paper");
}

#[test]
fn the_sweep_part_matches_a_fresh_run() {
    part_matches("sweep");
}

#[test]
fn the_strain_part_matches_a_fresh_run() {
    part_matches("strain");
}

#[test]
fn the_steering_part_matches_a_fresh_run() {
    part_matches("steering");
}

#[test]
fn the_timing_part_matches_a_fresh_run() {
    part_matches("timing");
}

#[test]
fn the_trials_part_matches_a_fresh_run() {
    part_matches("trials");
}

#[test]
fn an_unknown_part_is_refused_naming_the_parts() {
    let o = validate(&repo().join("docs/validation.md"), "everything");
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        e.contains(
            "no part `everything`: one of plans, paper, sweep, strain, steering, timing, trials"
        ),
        "{e}"
    );
}

/// docs/strain.md quotes the standing comparison with the torque bias from docs/validation.md's
/// `strain` block (which `the_strain_part_matches_a_fresh_run` holds to the code): the same RMS,
/// worst gauge's error and largest prediction, so the quote cannot outlive a change of them.
#[test]
fn the_strain_guide_quotes_the_strain_block_of_the_validation() {
    let validation = std::fs::read_to_string(repo().join("docs/validation.md")).unwrap();
    let block = validation
        .split("<!-- generated: strain -->")
        .nth(1)
        .and_then(|b| b.split("<!-- end generated -->").next())
        .expect("docs/validation.md has a generated `strain` block");
    let on = block
        .lines()
        .find(|l| l.starts_with("| on |"))
        .expect("the strain block has a row `on` (torque bias on)");
    // | on | 2.46 % | 0.999 | RF_troch_axial 15.0 microstrain | 470.6 microstrain |
    let cells: Vec<&str> = on.split('|').map(str::trim).collect();
    let rms = cells[2];
    let worst = cells[4].split_whitespace().nth(1).unwrap();
    let largest = cells[5].split_whitespace().next().unwrap();
    let number = |s: &str| s.trim_end_matches(" %").parse::<f64>().unwrap();
    let strain = std::fs::read_to_string(repo().join("docs/strain.md")).unwrap();
    let quote = format!(
        "Standing with the torque bias, simulated against predicted: {rms} RMS, no gauge off by more than\n{} microstrain of up to {}",
        number(worst).round(),
        number(largest).round()
    );
    assert!(
        strain.contains(&quote),
        "docs/strain.md should quote docs/validation.md's strain block as\n{quote}"
    );
}

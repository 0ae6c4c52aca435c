//! `dbot calibrate` and `dbot replay` on a stand-in's standing trial with strain
//! (`lab::identify::stand_in::write_standing_trial`: servos reading 0.8 x torque + 0.05 N m, a
//! strain board of known gains): the calibration is written and a model file naming it makes
//! `dbot replay` read the load and the gauges through it, saying so beside each figure; a
//! calibration file with a bad gauge gain is refused naming the file and the gauge. With
//! `--against replay` the file says what it was fitted against; an unknown `--against` is
//! refused in Python's words.

use crate::board_fakes;
use board_fakes::cli::{fails_naming, run, strings};

#[test]
fn calibrate_writes_a_calibration_a_model_names_and_replay_reads_through_it() {
    let dir = tempfile::tempdir().unwrap();
    let default = planner::model::builtin("drosophibot2").unwrap();
    let options = planner::excitation::ExcitationOptions {
        hold_s: 0.2,
        posture_s: 1.5,
        ..Default::default()
    };
    let truth = lab::identify::stand_in::reading_stand_in_model(&default);
    let trial =
        lab::identify::stand_in::write_standing_trial(&truth, &default, &options, dir.path())
            .unwrap();
    let trial = trial.to_str().unwrap();
    // `dbot calibrate TRIAL --model drosophibot2 --out OUT` with `extra`: what it printed, and the
    // file's `against` line.
    let calibrate = |extra: &[&str], out: &str| {
        let mut args = vec!["calibrate", trial, "--model", "drosophibot2", "--out", out];
        args.extend_from_slice(extra);
        let d = run(dir.path(), &strings(&args));
        assert!(d.status.success(), "{}{}", d.stdout, d.stderr);
        let cal = std::fs::read_to_string(dir.path().join(out)).unwrap();
        let against = cal
            .lines()
            .find(|l| l.starts_with("against = "))
            .map(str::to_owned);
        (
            d.stdout,
            against.unwrap_or_else(|| panic!("no against line in\n{cal}")),
        )
    };
    let (printed, against) = calibrate(&[], "cal.toml");
    assert!(
        printed.contains("calibrated:") && printed.contains("wrote cal.toml"),
        "{printed}"
    );
    assert_eq!(
        against,
        "against = \"the plan's static prediction of the model drosophibot2\""
    );
    let (_, against) = calibrate(&["--against", "replay"], "cal-replay.toml");
    assert_eq!(
        against,
        "against = \"the trial replayed on the body of the model drosophibot2\""
    );
    let bogus = run(
        dir.path(),
        &strings(&["calibrate", trial, "--against", "sim", "--out", "x.toml"]),
    );
    fails_naming(
        &bogus,
        "an unknown --against",
        &["against: \"sim\" is neither \"plan\"", "\"replay\""],
    );
    assert!(!dir.path().join("x.toml").exists());
    let text = planner::model::to_toml_string(&default, "", &|_| String::new());
    std::fs::write(
        dir.path().join("m.toml"),
        format!("calibration = \"cal.toml\"\n{text}"),
    )
    .unwrap();

    let estimate = run(
        dir.path(),
        &strings(&["replay", trial, "--model", "drosophibot2"]),
    );
    assert!(estimate.status.success(), "{}", estimate.stderr);
    let calibrated = run(
        dir.path(),
        &strings(&["replay", trial, "--model", "m.toml"]),
    );
    assert!(calibrated.status.success(), "{}", calibrated.stderr);
    let gauge_line = |out: &str| {
        out.lines()
            .find(|l| l.starts_with("LF_femur_axial"))
            .unwrap_or_else(|| panic!("no strain line in\n{out}"))
            .to_owned()
    };
    assert!(
        gauge_line(&estimate.stdout).ends_with("ESTIMATE (0.5000 counts per microstrain)"),
        "{}",
        estimate.stdout
    );
    assert!(
        gauge_line(&calibrated.stdout).contains("calibrated ("),
        "{}",
        calibrated.stdout
    );
    // The calibration file keeps the gauge's fitted gain; a bad one is refused, named.
    let cal = std::fs::read_to_string(dir.path().join("cal.toml")).unwrap();
    assert!(cal.contains("[gauge.LF_femur_axial]"), "{cal}");
    std::fs::write(
        dir.path().join("cal.toml"),
        "[gauge.LF_femur_axial]\ncounts_per_microstrain = 0\n",
    )
    .unwrap();
    let bad = run(
        dir.path(),
        &strings(&["replay", trial, "--model", "m.toml"]),
    );
    fails_naming(
        &bad,
        "a zero gauge gain",
        &["cal.toml", "gauge LF_femur_axial", "counts_per_microstrain"],
    );
}

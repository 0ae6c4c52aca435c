//! `dbot replay` and `dbot identify` on the stand-in robot's trial folders
//! (`lab::identify::stand_in`): a replay on the recording robot's own model is within the
//! servo's tick rounding (uniform: RMS tick / sqrt(12) = 0.44 mrad), on the default model far
//! from it; identification of a walk alone fits only the ground friction, here (feet that do not
//! slip) naming it as not identified.

use crate::board_fakes;
use board_fakes::cli::{run, strings};

/// The position RMS (mrad) `dbot replay` prints for `joint`.
fn position_mrad(stdout: &str, joint: &str) -> f64 {
    let line = stdout
        .lines()
        .find(|l| l.starts_with(joint))
        .unwrap_or_else(|| panic!("no line for {joint} in\n{stdout}"));
    line.split_whitespace().nth(1).unwrap().parse().unwrap()
}

#[test]
fn replay_and_identify_read_the_stand_ins_trial_folders() {
    let dir = tempfile::tempdir().unwrap();
    let default = planner::model::builtin("drosophibot2").unwrap();
    let options = planner::excitation::ExcitationOptions {
        hold_s: 0.3,
        chirp_s: 2.0,
        ..Default::default()
    };
    let joints = vec!["RH_TrF1".to_owned()];
    let t = lab::identify::stand_in::write_trials(&default, &options, &joints, dir.path()).unwrap();
    let truth = lab::identify::stand_in::stand_in_model(&default);
    let truth_file = dir.path().join("stand-in.toml");
    let text = planner::model::to_toml_string(&truth, "", &|_| String::new());
    std::fs::write(&truth_file, text).unwrap();
    let trial = t.suspended[0].to_str().unwrap();

    let own = run(
        dir.path(),
        &strings(&["replay", trial, "--model", truth_file.to_str().unwrap()]),
    );
    assert!(own.status.success(), "{}{}", own.stdout, own.stderr);
    let tick_mrad = std::f64::consts::TAU / 4096.0 * 1e3;
    assert!(
        position_mrad(&own.stdout, "RH_TrF1") <= 1.05 * tick_mrad / 12f64.sqrt(),
        "{}",
        own.stdout
    );
    assert!(own.stdout.contains("ESTIMATE"), "{}", own.stdout);
    let other = run(
        dir.path(),
        &strings(&["replay", trial, "--model", "drosophibot2"]),
    );
    assert!(
        position_mrad(&other.stdout, "RH_TrF1") > 5.0 * tick_mrad,
        "{}",
        other.stdout
    );

    let walk = t.walk.to_str().unwrap();
    // A walk alone: only the ground friction is fitted, and the stand-in's walk on the default
    // ground (1.5) does not slip, so it is named as not identified (with the servo dynamics).
    // The folder of --out does not exist yet: it is made.
    let d = run(
        dir.path(),
        &strings(&["identify", walk, "--out", "fits/fitted.toml"]),
    );
    assert!(d.status.success(), "{}{}", d.stdout, d.stderr);
    for line in [
        "not identified: servo dynamics",
        "not identified: foot_friction",
    ] {
        assert!(d.stdout.contains(line), "{line}: {}", d.stdout);
    }
    let fitted = planner::model::load(&dir.path().join("fits/fitted.toml")).unwrap();
    assert_eq!(fitted.foot_friction, None);
}

//! Every command ends or refuses within a bound (issue #30 items 1, 2 and 8): the inputs that
//! panicked, hung or repeated themselves. Each runs under a wall-clock bound far above what a
//! refusal needs (60 s), so a regression fails here instead of hanging the suite.

use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Runs dbot, killing it after `bound`; panics naming the command if it had to be killed.
fn dbot_within(args: &[&str], dir: &std::path::Path, bound: Duration) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_dbot"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let started = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed() > bound {
            child.kill().unwrap();
            panic!("dbot {} still running after {bound:?}", args.join(" "));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

const BOUND: Duration = Duration::from_secs(60);

fn refused_naming(o: &Output, needles: &[&str]) -> String {
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(!o.status.success(), "succeeded: {err}");
    assert!(!err.contains("panicked"), "panicked: {err}");
    for n in needles {
        assert!(err.contains(n), "stderr does not name `{n}`: {err}");
    }
    err
}

#[test]
fn baud_rates_no_mx_servo_supports_are_refused_at_parse() {
    let d = tempfile::tempdir().unwrap();
    // 0 divided the byte time by zero; 1 never answered.
    for rate in ["0", "1"] {
        let o = dbot_within(
            &["dxl", "--baud", rate, "-p", "/dev/null", "scan"],
            d.path(),
            BOUND,
        );
        refused_naming(
            &o,
            &["--baud", "not a rate an MX(2.0) servo supports", "57600"],
        );
        let o = dbot_within(&["sim-bus", "--baud", rate, "--link", "l"], d.path(), BOUND);
        refused_naming(&o, &["--baud", "not a rate an MX(2.0) servo supports"]);
    }
}

#[test]
fn a_spring_beyond_the_models_range_is_refused_naming_the_flag_and_range() {
    let d = tempfile::tempdir().unwrap();
    let o = dbot_within(
        &["plan", "--spring", "1e300", "--out", "p"],
        d.path(),
        BOUND,
    );
    refused_naming(&o, &["--spring", "1e300", "0 ..= 1e6 N m/rad"]);
}

#[test]
fn record_on_the_physics_robot_without_a_gait_ends_saying_why() {
    let d = tempfile::tempdir().unwrap();
    let o = dbot_within(
        &[
            "record",
            "--seconds",
            "1",
            "--port",
            "physics",
            "--out",
            "rec",
        ],
        d.path(),
        BOUND,
    );
    refused_naming(&o, &["physics", "no joints", "--play"]);
}

#[test]
fn an_aproj_with_a_nan_limit_is_refused_by_model_show_plan_and_export() {
    let d = tempfile::tempdir().unwrap();
    let seed = include_str!("../../../../fuzz/seeds/aproj/Drosobot2.aproj");
    let joint = seed.find("<Name>LF_CTr</Name>").unwrap();
    let lower = r#"<LimitPos Value="-47" Scale="None" />"#;
    let at = joint + seed[joint..].find(lower).unwrap();
    let bad = format!(
        r#"{}<LimitPos Value="NaN" Scale="None" />{}"#,
        &seed[..at],
        &seed[at + lower.len()..]
    );
    std::fs::write(d.path().join("bad.aproj"), bad).unwrap();
    for args in [
        &["model", "show", "--model", "bad.aproj"][..],
        &["plan", "--model", "bad.aproj", "--out", "p"][..],
        &[
            "model",
            "export",
            "--model",
            "bad.aproj",
            "--toml",
            "m.toml",
        ][..],
    ] {
        let o = dbot_within(args, d.path(), BOUND);
        refused_naming(&o, &["bad.aproj", "joint LF_CTr", "limits", "NaN"]);
    }
}

#[test]
fn an_error_says_its_cause_once() {
    let d = tempfile::tempdir().unwrap();
    let o = dbot_within(
        &["table", "--plan", "no-such-dir", "--out", "x.dbgt"],
        d.path(),
        BOUND,
    );
    let err = refused_naming(&o, &["no-such-dir"]);
    let cause = "No such file or directory";
    assert_eq!(err.matches(cause).count(), 1, "{err}");
}

#[test]
fn the_default_virtual_store_is_created_in_a_fresh_folder() {
    let d = tempfile::tempdir().unwrap();
    let o = dbot_within(&["gaits"], d.path(), BOUND);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(d.path().join("out/virtual-robot.flash").is_file(), "{err}");
}

#[test]
fn a_slot_beyond_the_last_is_out_of_range_not_empty() {
    let d = tempfile::tempdir().unwrap();
    let o = dbot_within(&["run", "--slot", "9", "--steps", "1"], d.path(), BOUND);
    let err = refused_naming(&o, &["no slot 9", "4 slots, 0 ..= 3"]);
    assert!(!err.contains("empty"), "{err}");
}

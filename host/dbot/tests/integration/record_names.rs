//! `dbot record` names its joints (issue 20 item 2) with and without --table, writes README.md
//! beside the CSV, reports missing telemetry, and leaves no torque.png of an earlier recording.

use crate::cli_support;
use firmware::testkit::SyntheticGait;

use cli_support::on_virtual;
use planner::model::builtin;
use planner::plan::table::servo_joints;

fn joint_column(csv: &std::path::Path) -> Vec<String> {
    let mut rd = csv::Reader::from_path(csv).unwrap();
    let col = rd
        .headers()
        .unwrap()
        .iter()
        .position(|h| h == "joint")
        .unwrap();
    let mut names: Vec<String> = rd.records().map(|r| r.unwrap()[col].to_string()).collect();
    names.sort();
    names.dedup();
    names
}

#[test]
fn record_names_joints_with_and_without_a_table() {
    let dir = tempfile::tempdir().unwrap();
    let t = dir.path().join("g.dbgt");
    std::fs::write(&t, SyntheticGait::new(100, 0.5).build()).unwrap();
    let run = |args: &[&str]| on_virtual(dir.path(), args);
    let ok = |o: &std::process::Output| {
        assert!(
            o.status.success(),
            "{}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        );
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    ok(&run(&["upload", "--table", t.to_str().unwrap()]));
    let m = builtin("drosophibot2").unwrap();
    let mut model_names: Vec<String> = servo_joints(&m)
        .into_iter()
        .map(|j| m.joints[j].name.clone())
        .collect();
    model_names.sort();
    let out = dir.path().join("rec");
    let o = out.to_str().unwrap();
    let table = t.to_str().unwrap();
    let stdout = ok(&run(&[
        "record", "--out", o, "--table", table, "--play", "0", "--steps", "1",
    ]));
    // Each recording is a new trial folder in --out: the last one indexed.
    let trial = || board::trial::latest_trial(&out).unwrap().unwrap();
    let first = trial();
    // The summary counts the cycle numbers the CSV skips (telemetry every cycle here). The virtual
    // robot's host takes every record the cycle it is made, so none is lost: the skipped cycles
    // are ones that made none (the torque switched on before the ramp).
    let text = std::fs::read_to_string(first.join("telemetry.csv")).unwrap();
    let mut cycles: Vec<u32> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect();
    cycles.dedup();
    let skipped: u32 = cycles.windows(2).map(|w| w[1] - w[0] - 1).sum();
    let expect = if skipped == 0 {
        "no telemetry record missing".to_string()
    } else {
        format!("no telemetry record lost ({skipped} bus cycle(s) made none")
    };
    assert!(stdout.contains(&expect), "{stdout} (expected `{expect}`)");
    assert_eq!(joint_column(&first.join("telemetry.csv")), model_names);
    assert!(first.join("torque.png").exists());
    let readme = std::fs::read_to_string(first.join("README.md")).unwrap();
    assert!(readme.contains("8 = torque off"), "{readme}");

    // Without --table: the names from the board's joint-map order, and no stale torque plot.
    ok(&run(&["record", "--out", o, "--play", "0", "--steps", "1"]));
    let second = trial();
    assert_ne!(second, first);
    assert_eq!(joint_column(&second.join("telemetry.csv")), model_names);
    assert!(!second.join("torque.png").exists());
    assert!(second.join("angles.png").exists());
}

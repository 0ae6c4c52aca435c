//! `dbot record` writes trials (issue 29 item 1) and never loses one (issue 30 item 4); `record
//! --table` and `run --table` put the user's gait into the freshly opened robot before walking
//! (issue 30 item 9: `upload --port physics` is lost when the command exits, so until now no
//! command could walk a user's own gait on the physics robot).

use crate::board_fakes;
use std::path::Path;

use board::trial::{Outcome, latest_trial, list_trials, read_trial};
use board_fakes::cli::{fails_naming, record_args, run, strings, table, tree};
use protocol::GaitTable;

fn record(out: &Path, t: &str, port: &str, extra: &[&str]) -> Vec<String> {
    let mut a = record_args(out, t, port, &["--steps", "1"]);
    a.extend(strings(extra));
    a
}

#[test]
fn a_recording_on_a_fresh_robot_is_a_trial_with_its_metadata() {
    let dir = tempfile::tempdir().unwrap();
    let t = table(dir.path(), "g.dbgt", 40, 0.4);
    let bytes = std::fs::read(&t).unwrap();
    let gait = GaitTable::parse(&bytes).unwrap();
    let trials = dir.path().join("trials");
    // `virtual` boots empty: --table uploads the gait before --play plays it (before: "slot 0
    // is empty").
    let d = run(
        dir.path(),
        &record(
            &trials,
            &t,
            "virtual",
            &["--notes", "first-try", "--backward"],
        ),
    );
    assert!(d.status.success(), "{}{}", d.stdout, d.stderr);
    assert!(d.stdout.contains("slot 0: uploaded"), "{}", d.stdout);
    let path = latest_trial(&trials).unwrap().unwrap();
    assert!(
        d.stdout.contains(&path.display().to_string()),
        "{}",
        d.stdout
    );
    let tr = read_trial(&path).unwrap();
    let m = &tr.meta;
    assert_eq!(m.outcome, Outcome::Complete);
    assert_eq!(m.folder, path.file_name().unwrap().to_string_lossy());
    let g = m.gait.as_ref().unwrap();
    assert_eq!(
        (g.name.as_str(), g.crc, g.slot),
        ("synthetic", gait.crc(), Some(0))
    );
    assert_eq!(g.step_period_s, 0.4);
    assert_eq!(m.direction, Some(protocol::Direction::Backward));
    assert_eq!((m.period_scale, m.steps), (Some(1.0), Some(1)));
    assert_eq!(m.notes, "first-try");
    assert!(
        m.command_line.iter().any(|a| a == "first-try"),
        "{:?}",
        m.command_line
    );
    assert_eq!(m.port, "virtual");
    assert_eq!(m.firmware.protocol_version, protocol::PROTOCOL_VERSION);
    assert_eq!(m.host_version, env!("CARGO_PKG_VERSION"));
    assert_eq!(m.settings.bus_baud, 1_000_000);
    assert_eq!(m.settings.joints.len(), 22);
    assert!(!m.strain && m.perturbation.is_none() && m.plan.is_none());
    assert_eq!(m.joints.len(), 22);
    assert_eq!(tr.rows.len(), m.cycles * 22);
    assert!(
        m.cycles > 40,
        "{} cycles for a 0.4 s step and its ramp",
        m.cycles
    );
}

#[test]
fn a_failed_or_refused_record_never_touches_a_good_trial() {
    let dir = tempfile::tempdir().unwrap();
    let t = table(dir.path(), "g.dbgt", 40, 0.4);
    let image = format!("virtual:{}", dir.path().join("robot.flash").display());
    let trials = dir.path().join("trials");
    let d = run(dir.path(), &record(&trials, &t, &image, &["--every", "4"]));
    assert!(d.status.success(), "{}", d.stderr);
    // A second recording in a row: a folder of its own.
    let d = run(dir.path(), &record(&trials, &t, &image, &[]));
    assert!(d.status.success(), "{}", d.stderr);
    let listed = list_trials(&trials).unwrap();
    assert_eq!(listed.len(), 2);
    assert_ne!(listed[0].folder, listed[1].folder);
    let good = tree(&trials);
    let store = std::fs::read(dir.path().join("robot.flash")).unwrap();
    // A rate the 2 s silence limit cannot serve (before: a few rows, then "no telemetry for
    // 2 s", over the good recording) is refused up front, naming both numbers.
    let d = run(
        dir.path(),
        &record(&trials, &t, &image, &["--every", "300"]),
    );
    fails_naming(&d, "--every 300", &["300", "100 Hz", "199"]);
    // A named trial folder that exists is refused before anything moves.
    let taken = listed[0].folder.clone();
    let d = run(
        dir.path(),
        &record(&trials, &t, &image, &["--trial", &taken]),
    );
    fails_naming(&d, "--trial of an existing trial", &[&taken, "exists"]);
    // A folder of trials that cannot be made.
    let file = dir.path().join("g.dbgt");
    let d = run(dir.path(), &record(&file.join("x"), &t, &image, &[]));
    fails_naming(&d, "--out under a file", &["g.dbgt"]);
    assert_eq!(tree(&trials), good, "a good trial or the index changed");
    assert_eq!(
        std::fs::read(dir.path().join("robot.flash")).unwrap(),
        store,
        "the robot's store changed"
    );
}

#[test]
fn the_physics_robot_walks_the_users_gait_from_one_command() {
    let dir = tempfile::tempdir().unwrap();
    let t = table(dir.path(), "g.dbgt", 40, 0.4);
    let crc = GaitTable::parse(&std::fs::read(&t).unwrap()).unwrap().crc();
    let trials = dir.path().join("trials");
    let d = run(dir.path(), &record(&trials, &t, "physics", &[]));
    assert!(d.status.success(), "{}{}", d.stdout, d.stderr);
    let tr = read_trial(&latest_trial(&trials).unwrap().unwrap()).unwrap();
    assert_eq!(tr.meta.gait.as_ref().unwrap().crc, crc);
    assert_eq!(tr.meta.port, "physics:flat");
    // The walk reached its one step: the last records are of step 1, after the ramp.
    assert_eq!(tr.rows.last().unwrap().step, 1);
    // `run --table` too.
    let d = run(
        dir.path(),
        &strings(&[
            "run",
            "--port",
            "physics",
            "--table",
            &t,
            "--steps",
            "1",
            "--allow-infeasible",
        ]),
    );
    assert!(d.status.success(), "{}{}", d.stdout, d.stderr);
    assert!(d.stdout.contains("slot 0: uploaded"), "{}", d.stdout);
}

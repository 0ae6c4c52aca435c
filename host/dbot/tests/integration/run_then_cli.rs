//! `dbot run --then` as a process on the virtual robot (`--port virtual:PATH`): the queued gaits
//! take over at their step boundaries without a stand (the run's board time equals one gait's run
//! of as many steps), each switch is reported, and a gait that cannot follow is refused with the
//! switch rule's reason.

use crate::cli_support;
use std::f64::consts::PI;
use std::path::Path;

use firmware::testkit::{JOINTS, SyntheticGait};
use protocol::gait::GaitTableBuilder;

use cli_support::on_virtual as dbot;

/// Uploads here give `--allow-infeasible`: the synthetic gaits are faster than an MX-28 follows
/// with their torques (a table file meets the servo rule at every door); the board is the test.
fn ok(dir: &Path, args: &[&str]) -> String {
    let o = dbot(dir, args);
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        o.status.success(),
        "dbot {args:?} failed:\n{out}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    out
}

/// The synthetic gait (100 slices, 0.5 s) with `extra(slice)` rad added to every angle.
fn variant(dir: &Path, file: &str, extra: impl Fn(usize) -> f64) -> String {
    let g = SyntheticGait::new(100, 0.5);
    let mut b = GaitTableBuilder::new("variant", g.period_s, 0.5, g.joints.clone());
    for s in 0..g.slices {
        let angles: Vec<f64> = (0..JOINTS).map(|j| g.angle(s, j) + extra(s)).collect();
        let torques: Vec<f64> = (0..JOINTS).map(|j| g.torque(s, j)).collect();
        b.slice(
            if s < 50 { 0b010_101 } else { 0b101_010 },
            &angles,
            &torques,
        );
    }
    let path = dir.join(file);
    std::fs::write(&path, b.build().unwrap()).unwrap();
    path.display().to_string()
}

/// The board time of a `done:` line, s.
fn board_s(out: &str) -> f64 {
    out.split("walked in ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .unwrap()
        .parse()
        .unwrap()
}

/// `dbot upload --table TABLE --slot SLOT --allow-infeasible` in `d` (the synthetic variants are
/// not planned for the servos; the override is what this file's tests are not about).
fn upload(d: &Path, table: &str, slot: u8) {
    ok(
        d,
        &[
            "upload",
            "--table",
            table,
            "--slot",
            &slot.to_string(),
            "--allow-infeasible",
        ],
    );
}

#[test]
fn then_plays_the_queued_gaits_at_step_boundaries_without_a_stand() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let straight = variant(d, "straight.dbgt", |_| 0.0);
    // Slice 0 unchanged (sin 0 = 0): it may follow the straight gait at a step boundary.
    let curve = variant(d, "curve.dbgt", |s| {
        0.05 * (2.0 * PI * s as f64 / 100.0).sin()
    });
    upload(d, &straight, 0);
    upload(d, &curve, 1);
    let one = ok(d, &["run", "--slot", "0", "--steps", "6"]);
    let out = ok(
        d,
        &[
            "run", "--slot", "0", "--steps", "2", "--then", "1", "--then", "0:back",
        ],
    );
    let first = out
        .find("step 2: slot 1 forward follows without a stop")
        .unwrap_or_else(|| panic!("{out}"));
    let second = out
        .find("step 4: slot 0 backward follows without a stop")
        .unwrap_or_else(|| panic!("{out}"));
    assert!(first < second, "{out}");
    assert!(out.contains("done: 6 steps walked in "), "{out}");
    assert!(out.contains("no fault; the robot stands"), "{out}");
    // The same ramp from the same boot posture, then 6 steps of 0.5 s either way: a stand or a
    // second ramp (at least 0.5 s) between gaits would show; both are read at 100 ms polls.
    let (t_one, t_then) = (board_s(&one), board_s(&out));
    assert!(t_one >= 3.0, "{one}");
    assert!(
        (t_then - t_one).abs() <= 0.2,
        "6 steps in {t_one} s, with --then {t_then} s"
    );
}

#[test]
fn a_gait_that_cannot_follow_is_refused_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let straight = variant(d, "straight.dbgt", |_| 0.0);
    // 0.1 rad on every joint at slice 0: more than an MX-28 turns in one 100 Hz cycle (0.0576).
    let shifted = variant(d, "shifted.dbgt", |_| 0.1);
    upload(d, &straight, 0);
    upload(d, &shifted, 2);
    let o = dbot(d, &["run", "--slot", "0", "--steps", "1", "--then", "2"]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        e.contains("queueing slot 2 after the gait before it")
            && e.contains("joint 0 would jump 0.1000 rad at the switch")
            && e.contains("(0.0575 rad)"),
        "{e}"
    );
}

//! Every board command of `dbot` run as a process against the virtual robot whose flash lives in
//! a file (`--port virtual:PATH`), checking what each command reports and what the board then holds.

use std::path::Path;
use std::process::{Command, Output};

use firmware::testkit::SyntheticGait;

fn dbot(dir: &Path, args: &[&str]) -> Output {
    let image = dir.join("robot.flash");
    let out = Command::new(env!("CARGO_BIN_EXE_dbot"))
        .args(args)
        .arg("--port")
        .arg(format!("virtual:{}", image.display()))
        .current_dir(dir)
        .env_remove("DBOT_CONFIG")
        .env("XDG_CONFIG_HOME", dir)
        .output()
        .unwrap();
    out
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn ok(dir: &Path, args: &[&str]) -> String {
    let o = dbot(dir, args);
    assert!(
        o.status.success(),
        "dbot {args:?} failed:\n{}{}",
        stdout(&o),
        stderr(&o)
    );
    stdout(&o)
}

fn table(dir: &Path, name: &str, slices: usize, period: f64) -> String {
    let path = dir.join(name);
    std::fs::write(&path, SyntheticGait::new(slices, period).build()).unwrap();
    path.display().to_string()
}

#[test]
fn upload_then_gaits_in_another_process_sees_the_gait() {
    let dir = tempfile::tempdir().unwrap();
    let t = table(dir.path(), "a.dbgt", 100, 1.0);
    let out = ok(dir.path(), &["upload", "--table", &t, "--slot", "1"]);
    assert!(
        out.contains("slot 1: \"synthetic\" 22 joints x 100 slices, step 1.000 s"),
        "{out}"
    );
    assert!(out.contains("the slot was empty"), "{out}");
    let out = ok(dir.path(), &["gaits"]);
    assert!(out.contains("slot 0: empty"), "{out}");
    assert!(
        out.contains("slot 1: \"synthetic\" 22 joints x 100 slices"),
        "{out}"
    );
    let t2 = table(dir.path(), "b.dbgt", 50, 0.5);
    let out = ok(dir.path(), &["upload", "--table", &t2, "--slot", "1"]);
    assert!(
        out.contains("replaced: \"synthetic\" 22 joints x 100 slices"),
        "{out}"
    );
}

#[test]
fn run_walks_the_steps_and_status_estop_set_work() {
    let dir = tempfile::tempdir().unwrap();
    let t = table(dir.path(), "a.dbgt", 100, 0.5);
    ok(dir.path(), &["upload", "--table", &t, "--slot", "0"]);
    let out = ok(dir.path(), &["run", "--slot", "0", "--steps", "4"]);
    // 4 steps of 0.5 s after a ramp of at least 0.5 s: the board clock shows at least 2.5 s.
    let t_end: f64 = out
        .split("board clock ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .unwrap()
        .parse()
        .unwrap();
    assert!(t_end >= 2.5, "{out}");
    let out = ok(
        dir.path(),
        &[
            "run",
            "--slot",
            "0",
            "--steps",
            "1",
            "--backward",
            "--period",
            "1.0",
        ],
    );
    assert!(out.contains("the robot stands"), "{out}");
    let out = ok(dir.path(), &["status"]);
    assert!(out.contains("state     Idle"), "{out}");
    let out = ok(dir.path(), &["estop"]);
    assert!(
        out.contains("Fault") && out.contains("EmergencyStop"),
        "{out}"
    );
    let out = ok(dir.path(), &["stop"]);
    assert!(out.contains("nothing to stop"), "{out}");
    let out = ok(dir.path(), &["set", "--rate", "200", "--baud", "2000000"]);
    assert!(out.contains("bus 2000000 bit/s at 200 Hz"), "{out}");
    let out = ok(dir.path(), &["servos", "--table", &t]);
    assert!(out.contains("    0      1   Mx28"), "{out}");
}

#[test]
fn bad_requests_name_the_problem() {
    let dir = tempfile::tempdir().unwrap();
    let o = dbot(dir.path(), &["run", "--slot", "2", "--steps", "1"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("slot 2 is empty"), "{}", stderr(&o));
    let bad = dir.path().join("bad.dbgt");
    std::fs::write(&bad, b"not a table").unwrap();
    let o = dbot(dir.path(), &["upload", "--table", bad.to_str().unwrap()]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("bad.dbgt is not a valid step table"),
        "{}",
        stderr(&o)
    );
    let t = table(dir.path(), "a.dbgt", 100, 1.0);
    ok(dir.path(), &["upload", "--table", &t]);
    let o = dbot(dir.path(), &["run", "--steps", "1", "--period", "50"]);
    assert!(stderr(&o).contains("--period 50 s"), "{}", stderr(&o));
}

//! Every board command of `dbot` run as a process against the virtual robot whose flash lives in
//! a file (`--port virtual:PATH`), checking what each command reports and what the board then holds.

use crate::cli_support;
use std::path::Path;
use std::process::Command;

use cli_support::{in_dir, on_virtual as dbot, stderr, stdout};

use firmware::testkit::SyntheticGait;

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
    // It names the gait it is about to play, and how.
    assert!(
        out.contains("slot 0: \"synthetic\" 22 joints x 100 slices, step 0.500 s"),
        "{out}"
    );
    assert!(
        out.contains("; playing 4 steps forward at 0.500 s per step"),
        "{out}"
    );
    // 4 steps of 0.5 s after a ramp of at least 0.5 s: at least 2.5 s on the board's clock.
    assert!(out.contains("done: 4 steps walked in "), "{out}");
    assert!(
        out.contains("0 overrun(s), 0 bus error(s), no fault"),
        "{out}"
    );
    let t_end: f64 = out
        .split("walked in ")
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
    assert!(out.contains("state     Idle (torque off)"), "{out}");
    let out = ok(dir.path(), &["estop"]);
    assert!(
        out.contains("in state Fault (torque off)") && out.contains("emergency stop by the host"),
        "{out}"
    );
    assert!(!out.contains("Some("), "no debug text: {out}");
    // Its advice works: the virtual robot has booted afresh, so there is no fault left.
    assert!(out.contains("starts afresh"), "{out}");
    let out = ok(dir.path(), &["set", "--clear-fault"]);
    assert!(
        out.contains("no fault to clear (the board is in state Idle"),
        "{out}"
    );
    let out = ok(dir.path(), &["stop"]);
    assert!(out.contains("nothing to stop"), "{out}");
    let out = ok(dir.path(), &["set", "--rate", "150"]);
    assert!(out.contains("bus 1000000 bit/s at 150 Hz"), "{out}");
    // Kept as a board keeps it: the next command (a fresh boot of the virtual robot) sees it.
    let out = ok(dir.path(), &["status"]);
    assert!(out.contains("bus       1000000 bit/s, 150 Hz"), "{out}");
    // A baud change of the board alone strands the servos (they keep their EEPROM baud), as the
    // virtual ones now do: it is undone and refused, naming the servo and the command that moves
    // the servos first. (The virtual robot used to set its servos silently and take it.)
    let o = dbot(dir.path(), &["set", "--baud", "2000000"]);
    assert!(
        !o.status.success(),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    let e = stderr(&o);
    assert!(
        e.contains("baud 2000000: the servo of joint ")
            && e.contains(
                " did not answer at 2000000 bit/s, so the board is back at 1000000 bit/s"
            ),
        "{e}"
    );
    assert!(
        e.contains("dbot dxl setup -p ADAPTER --id N --new-baud 2000000"),
        "{e}"
    );
    let out = ok(dir.path(), &["status"]);
    assert!(out.contains("bus       1000000 bit/s, 150 Hz"), "{out}");
    assert!(!out.contains("Fault"), "{out}");
    let out = ok(dir.path(), &["servos", "--table", &t]);
    assert!(out.contains("    0      1  MX-28(2.0)"), "{out}");
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
    assert!(
        stderr(&o).contains("period 50 s: the planned step"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn the_setup_file_names_port_and_slot_and_flags_override_it() {
    let dir = tempfile::tempdir().unwrap();
    let t = table(dir.path(), "a.dbgt", 100, 0.5);
    std::fs::write(
        dir.path().join("dbot.toml"),
        "port = \"virtual:setup.flash\"\nslot = 2\n",
    )
    .unwrap();
    let plain = |args: &[&str]| in_dir(dir.path()).args(args).output().unwrap();
    let o = plain(&["upload", "--table", &t, "--create"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("slot 2:"), "{}", stdout(&o));
    assert!(dir.path().join("setup.flash").is_file());
    // Daily use: `dbot run --steps K` plays the setup's slot on the setup's port.
    let o = plain(&["run", "--steps", "1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    // A flag wins over the file: another flash image has nothing in slot 2.
    let o = plain(&["gaits", "--port", "virtual:other.flash", "--create"]);
    assert!(stdout(&o).contains("slot 2: empty"), "{}", stdout(&o));
    // A bad setup file is named with the problem.
    std::fs::write(dir.path().join("dbot.toml"), "rate = 5\n").unwrap();
    let o = plain(&["gaits"]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("dbot.toml: rate = 5 is out of range"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn upload_from_a_plan_directory_builds_the_table_of_that_plan() {
    let dir = tempfile::tempdir().unwrap();
    let o = in_dir(dir.path())
        .args(["plan", "--preset", "table1", "--out", "p", "--slices", "50"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    // The original solver's 0.5 s swing (--preset table1) turns the front CTr (MX-64) and FTi
    // (MX-28) faster than their servos can (about 6.6 and 6.1 rad/s against 6.60 and 5.76 rad/s
    // no-load speed).
    let o = dbot(dir.path(), &["upload", "--plan", "p", "--slot", "3"]);
    let e = stderr(&o);
    assert!(!o.status.success());
    for needle in [
        "cannot follow",
        "LF_FTi at slice",
        "no-load speed 5.76 rad/s by",
        "--allow-infeasible",
    ] {
        assert!(e.contains(needle), "{needle}: {e}");
    }
    let table = |extra: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_dbot"))
            .args(["table", "--plan", "p", "--out", "t.dbgt"])
            .args(extra)
            .current_dir(dir.path())
            .output()
            .unwrap()
    };
    let o = table(&[]);
    assert!(
        !o.status.success() && stderr(&o).contains("LF_FTi at slice"),
        "{}",
        stderr(&o)
    );
    assert!(!dir.path().join("t.dbgt").exists());
    let o = table(&["--allow-infeasible"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = ok(
        dir.path(),
        &["upload", "--plan", "p", "--slot", "3", "--allow-infeasible"],
    );
    // 22 servos of Drosophibot II, the 50 slices asked for, table 1's 1.25 s step period; named
    // as `dbot table --plan p` names it (the plan directory's name).
    assert!(
        out.contains("slot 3: \"p\" 22 joints x 50 slices, step 1.250 s, duty 0.60"),
        "{out}"
    );
    // The default plan (servo-safe, swing 1.0 s) is built without the override.
    let o = in_dir(dir.path())
        .args(["plan", "--out", "q", "--slices", "50"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let o = in_dir(dir.path())
        .args(["table", "--plan", "q", "--out", "q.dbgt"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let o = dbot(dir.path(), &["upload", "--plan", "nowhere"]);
    assert!(stderr(&o).contains("nowhere/plan.json"), "{}", stderr(&o));
}

#[test]
fn devices_lists_no_board_here_and_says_how_to_go_virtual() {
    let o = Command::new(env!("CARGO_BIN_EXE_dbot"))
        .arg("devices")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    // CI machines have no board: the one line says which VID:PID was looked for.
    if out.starts_with("no board found") {
        assert!(out.contains("1209:0001"), "{out}");
    }
}

#[test]
fn a_flash_image_of_the_wrong_size_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("robot.flash"), [0u8; 100]).unwrap();
    let o = dbot(dir.path(), &["gaits"]);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("robot.flash") && e.contains("100 bytes is not a flash image"),
        "{e}"
    );
}

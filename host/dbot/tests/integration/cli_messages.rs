//! What `dbot` says to a user, one test per message: the setup file's keys and paths, a mistyped
//! virtual store, `dxl` on things that are not serial ports and on servos at another baud, and
//! `--help` of every command.

use crate::cli_support;
use crate::sim_bus_support;
use std::path::Path;
use std::process::Output;

use cli_support::{in_dir, text};

fn dbot(dir: &Path, args: &[&str]) -> Output {
    in_dir(dir)
        .args(args)
        .env("HOME", dir)
        .env("RUST_BACKTRACE", "0")
        .output()
        .unwrap()
}

#[test]
fn a_mistyped_virtual_store_is_an_error_naming_it_and_create_makes_it() {
    let dir = tempfile::tempdir().unwrap();
    let o = dbot(dir.path(), &["gaits", "--port", "virtual:robto.flash"]);
    assert!(!o.status.success());
    assert!(
        text(&o).contains("virtual robot store robto.flash does not exist (from --port)")
            && text(&o).contains("--create"),
        "{}",
        text(&o)
    );
    assert!(!dir.path().join("robto.flash").exists());
    let o = dbot(
        dir.path(),
        &["gaits", "--port", "virtual:lab/r.flash", "--create"],
    );
    assert!(text(&o).contains("no such folder lab"), "{}", text(&o));
    let o = dbot(
        dir.path(),
        &["gaits", "--port", "virtual:r.flash", "--create"],
    );
    assert!(o.status.success(), "{}", text(&o));
    assert!(dir.path().join("r.flash").is_file());
}

#[test]
fn the_setup_files_paths_are_relative_to_it_and_its_model_is_planned() {
    let dir = tempfile::tempdir().unwrap();
    let lab = dir.path().join("lab");
    std::fs::create_dir(&lab).unwrap();
    std::fs::write(
        lab.join("dbot.toml"),
        "port = \"virtual:robot.flash\"\nmodel = \"scale-drosophila\"\n",
    )
    .unwrap();
    let cfg = lab.join("dbot.toml");
    let cfg = cfg.to_str().unwrap();
    // Run from the parent folder: the store is lab/robot.flash, not ./robot.flash.
    let o = dbot(dir.path(), &["gaits", "--config", cfg, "--create"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(lab.join("robot.flash").is_file());
    assert!(!dir.path().join("robot.flash").exists());
    // A mistyped port in the file is named as the file's.
    std::fs::write(lab.join("dbot.toml"), "port = \"virtual:robto.flash\"\n").unwrap();
    let o = dbot(dir.path(), &["gaits", "--config", cfg]);
    assert!(
        text(&o).contains("(from the setup file's port)"),
        "{}",
        text(&o)
    );
    // `plan` without --model plans the setup file's model.
    std::fs::write(lab.join("dbot.toml"), "model = \"scale-drosophila\"\n").unwrap();
    let o = dbot(
        dir.path(),
        &[
            "plan",
            "--config",
            cfg,
            "--no-dynamics",
            "--slices",
            "20",
            "--out",
            "p",
        ],
    );
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).starts_with("scale-drosophila: 20 slices"),
        "{}",
        text(&o)
    );
    let json = std::fs::read_to_string(dir.path().join("p/plan.json")).unwrap();
    assert!(
        json.contains("\"model_source\": \"scale-drosophila\""),
        "{json}"
    );
}

#[test]
fn a_negative_swing_needs_no_equals_sign_and_is_refused_by_the_planner() {
    let dir = tempfile::tempdir().unwrap();
    let o = dbot(
        dir.path(),
        &["plan", "--swing", "-0.5", "--no-dynamics", "--out", "p"],
    );
    assert!(!o.status.success());
    let t = text(&o);
    assert!(!t.contains("unexpected argument"), "{t}");
    assert!(t.contains("swing"), "{t}");
}

#[test]
fn dxl_on_dev_null_or_a_regular_file_says_what_it_is() {
    let dir = tempfile::tempdir().unwrap();
    let o = dbot(dir.path(), &["dxl", "scan", "-p", "/dev/null"]);
    assert!(!o.status.success());
    assert!(
        text(&o).contains("/dev/null is a device but not a serial port"),
        "{}",
        text(&o)
    );
    assert!(!text(&o).contains("typewriter"), "{}", text(&o));
    std::fs::write(dir.path().join("notes.txt"), "x").unwrap();
    let o = dbot(dir.path(), &["dxl", "scan", "-p", "notes.txt"]);
    assert!(
        text(&o).contains("notes.txt is a regular file, not a serial port"),
        "{}",
        text(&o)
    );
}

#[test]
fn dxl_scan_at_the_wrong_baud_hints_and_baud_auto_finds_the_servos() {
    // Servos at 1 Mbit/s, as on the robot's bus; dxl at its (and sim-bus's) default 57600.
    let bus = sim_bus_support::SimBus::start(2, 1_000_000, 0);
    let link = bus.link().to_str().unwrap().to_owned();
    let dir = tempfile::tempdir().unwrap();
    let scan = |baud: &[&str]| {
        let mut a = vec!["dxl", "scan", "-p", &link, "--max-id", "3"];
        a.extend_from_slice(baud);
        a.extend(["--reply-slack-us", "300000"]);
        dbot(dir.path(), &a)
    };
    let o = scan(&[]);
    assert!(!o.status.success());
    assert!(
        text(&o).contains("no servo answers on")
            && text(&o)
                .contains("at 57600 bit/s: try another rate (baud 1000000) or baud auto (dbot dxl --baud, Bench.open(baud=))"),
        "{}",
        text(&o)
    );
    let o = scan(&["--baud", "auto"]);
    assert!(o.status.success(), "{}\n{}", text(&o), bus.log());
    assert!(
        text(&o).contains("2 servo(s) found on") && text(&o).contains("at 1000000 bit/s"),
        "{}",
        text(&o)
    );
}

#[test]
fn every_command_has_help_with_an_example_or_defaults() {
    let dir = tempfile::tempdir().unwrap();
    for cmd in [
        "demo", "plan", "model", "table", "compare", "devices", "upload", "gaits", "run", "stop",
        "estop", "status", "servos", "set", "record", "sim-bus", "dxl",
    ] {
        let o = dbot(dir.path(), &[cmd, "--help"]);
        let t = text(&o);
        assert!(
            t.contains("Examples:") || t.contains("Example:"),
            "{cmd}: {t}"
        );
        assert!(t.contains(&format!("dbot {cmd}")), "{cmd}: {t}");
    }
    let t = text(&dbot(dir.path(), &["dxl", "--help"]));
    assert!(
        t.contains("-p, --port") && t.contains("[default: 57600]"),
        "{t}"
    );
    let t = text(&dbot(dir.path(), &["sim-bus", "--help"]));
    assert!(
        t.contains("--return-delay-us") && t.contains("[default: 57600]"),
        "{t}"
    );
    assert!(
        !t.contains("--return-delay <"),
        "the old flag is hidden: {t}"
    );
    let t = text(&dbot(dir.path(), &["compare", "--help"]));
    assert!(t.contains("[default: out/compare]"), "{t}");
}

/// `dbot model show` says what drives each joint in words (issue 25 item 6), never the Rust
/// value (`Actuated { actuator: Generic, stiffness: 3.8e-8 }`). Expected from the model files:
/// LF_CTr of Drosophibot II is an MX-64(2.0) at 34.2857 N m/rad; the scale fly's joints are
/// generic actuators of 3.8e-8 N m/rad (paper section 3.1.2).
#[test]
fn model_show_says_what_drives_a_joint_in_words() {
    let dir = tempfile::tempdir().unwrap();
    let robot = text(&dbot(
        dir.path(),
        &["model", "show", "--model", "drosophibot2"],
    ));
    let ctr = robot.lines().find(|l| l.trim_start().starts_with("LF_CTr"));
    assert!(
        ctr.is_some_and(|l| l.ends_with("MX-64(2.0), stiffness 3.429e1 N m/rad")),
        "{robot}"
    );
    let fly = text(&dbot(
        dir.path(),
        &["model", "show", "--model", "scale-drosophila"],
    ));
    assert!(
        fly.contains("generic actuator, stiffness 3.800e-8 N m/rad"),
        "{fly}"
    );
    for out in [&robot, &fly] {
        assert!(
            !out.contains("Actuated") && !out.contains('{') && !out.contains("Fixed {"),
            "{out}"
        );
    }
}

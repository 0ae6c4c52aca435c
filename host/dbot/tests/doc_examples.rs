//! Every `dbot` command in the README's and docs/usage.md's `sh` blocks, run as written on the
//! virtual robot, in the order the documents give them, in one scratch folder.
//!
//! Board ports in the examples (`/dev/ttyACM0`, or none) become `--port virtual:robot.flash
//! --create`, so the examples share one virtual robot as they would share one board; an example
//! on the physics robot (`--port physics[:SCENE]`) runs there, as written. An example
//! whose comment starts `[needs a board]` or `[needs servos]` cannot run on the virtual robot
//! (recording a walk some other command started, a U2D2 adapter): it is listed, not run.

use std::path::{Path, PathBuf};
use std::process::Command;

/// Subcommands that talk to a board (and so take `--port`).
const BOARD_COMMANDS: [&str; 11] = [
    "devices", "upload", "gaits", "run", "stop", "estop", "status", "servos", "set", "record",
    "doctor",
];

/// One documented command: where it is, its words after `dbot`, whether it needs hardware.
#[derive(Debug)]
struct Example {
    at: String,
    args: Vec<String>,
    needs_hardware: bool,
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The `dbot` commands of the `sh` blocks of `file` (also `cargo run ... --bin dbot -- ARGS`).
fn examples(file: &str) -> Vec<Example> {
    let text = std::fs::read_to_string(repo().join(file)).unwrap();
    let mut in_sh = false;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let t = line.trim();
        if t.starts_with("```") {
            in_sh = !in_sh && t == "```sh";
            continue;
        }
        if !in_sh {
            continue;
        }
        let (cmd, comment) = match t.find(" #") {
            Some(k) => (&t[..k], t[k + 2..].trim()),
            None => (t, ""),
        };
        let rest = cmd
            .strip_prefix("dbot ")
            .or_else(|| cmd.split_once("--bin dbot -- ").map(|(_, r)| r));
        let Some(rest) = rest else { continue };
        assert!(
            !rest.contains(['"', '\'', '|', '>', '$']),
            "{file}:{}: the test runs plain words only: {t}",
            i + 1
        );
        out.push(Example {
            at: format!("{file}:{}", i + 1),
            args: rest.split_whitespace().map(str::to_owned).collect(),
            needs_hardware: comment.starts_with("[needs a board]")
                || comment.starts_with("[needs servos]"),
        });
    }
    out
}

/// The example's words with its board port replaced by the shared virtual robot (the physics
/// robot is kept: it runs here as anywhere).
fn on_virtual_robot(args: &[String]) -> Vec<String> {
    let physics = args
        .windows(2)
        .any(|w| (w[0] == "--port" || w[0] == "-p") && w[1].starts_with("physics"));
    if physics {
        return args.to_vec();
    }
    let mut a: Vec<String> = Vec::new();
    let mut words = args.iter();
    while let Some(w) = words.next() {
        if w == "--port" || w == "-p" {
            words.next();
        } else {
            a.push(w.clone());
        }
    }
    // `devices` only asks what a port is: it creates nothing.
    if a[0] == "devices" {
        a.extend(["--port", "virtual:robot.flash"].map(str::to_owned));
    } else if BOARD_COMMANDS.contains(&a[0].as_str()) {
        a.extend(["--port", "virtual:robot.flash", "--create"].map(str::to_owned));
    }
    a
}

#[test]
fn every_documented_dbot_command_runs_on_the_virtual_robot() {
    let dir = tempfile::tempdir().unwrap();
    // The commands run as from the repository's root: `dbot validate --check docs/validation.md`
    // reads the document (a copy, so that nothing here writes into the checkout).
    std::fs::create_dir(dir.path().join("docs")).unwrap();
    std::fs::copy(
        repo().join("docs/validation.md"),
        dir.path().join("docs/validation.md"),
    )
    .unwrap();
    // ... and its plots, which the check compares too.
    std::fs::create_dir(dir.path().join("docs/validation")).unwrap();
    for f in std::fs::read_dir(repo().join("docs/validation")).unwrap() {
        let f = f.unwrap().path();
        std::fs::copy(
            &f,
            dir.path()
                .join("docs/validation")
                .join(f.file_name().unwrap()),
        )
        .unwrap();
    }
    let all: Vec<Example> = ["README.md", "docs/usage.md"]
        .iter()
        .flat_map(|f| examples(f))
        .collect();
    assert!(
        all.len() >= 20,
        "found only {} examples: {all:?}",
        all.len()
    );
    let mut failed = Vec::new();
    let mut skipped = Vec::new();
    for e in &all {
        if e.needs_hardware {
            skipped.push(format!("{}: dbot {}", e.at, e.args.join(" ")));
            continue;
        }
        let args = on_virtual_robot(&e.args);
        let o = Command::new(env!("CARGO_BIN_EXE_dbot"))
            .args(&args)
            .current_dir(dir.path())
            .env_remove("DBOT_CONFIG")
            .env("XDG_CONFIG_HOME", dir.path())
            .env("HOME", dir.path())
            .output()
            .unwrap();
        if !o.status.success() {
            failed.push(format!(
                "{}: dbot {}\n{}{}",
                e.at,
                args.join(" "),
                String::from_utf8_lossy(&o.stdout),
                String::from_utf8_lossy(&o.stderr)
            ));
        }
    }
    eprintln!("not run (need hardware):\n  {}", skipped.join("\n  "));
    assert!(
        failed.is_empty(),
        "{} failed:\n{}",
        failed.len(),
        failed.join("\n")
    );
    // Only what truly needs hardware is skipped: recording a walk started elsewhere, and the
    // U2D2 examples. A new skip must be added here on purpose.
    let skipped_cmds: Vec<&str> = skipped
        .iter()
        .map(|s| s.split_once(": ").unwrap().1)
        .collect();
    assert_eq!(
        skipped_cmds,
        [
            "dbot record --out out/rec --table walk.dbgt --seconds 20 --port /dev/ttyACM0",
            "dbot dxl scan -p /dev/ttyUSB0 --baud auto",
            "dbot record --out rec --table gait.dbgt --seconds 20",
        ],
        "{skipped:?}"
    );
}

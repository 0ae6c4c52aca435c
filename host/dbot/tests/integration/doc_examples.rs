//! Every `dbot` command in the README's and docs/usage.md's `sh` blocks, run as written on the
//! virtual robot, in the order the documents give them.
//!
//! Board ports in the examples (`/dev/ttyACM0`, or none) become `--port virtual:robot.flash
//! --create`, so the examples of a group share one virtual robot as they would share one board; an
//! example on the physics robot (`--port physics[:SCENE]`) runs there, as written. An example
//! whose comment starts `[needs a board]` or `[needs servos]` cannot run on the virtual robot
//! (recording a walk some other command started, a U2D2 adapter): it is listed, not run.
//!
//! The examples fall into groups ([`Group`], by the document and the command), one test each, so
//! that nextest runs them in parallel; each group runs in a scratch folder of its own. A group that
//! reads what an example of another group writes (the README's plan `out/walk`) runs that example
//! first, as the reader of the documents would have. `dbot validate --check docs/validation.md` is
//! run by `validation_doc` (the same check, on a copy with one figure changed: every other block
//! must match), not a second time here.

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
/// robot is kept: it runs here as anywhere; so is the demo's, which names in-process robots only).
/// The demo walks 2 steps each way instead of 10 (`--steps 2`, unless the example gives `--steps`):
/// the same code in a fifth of the simulated time; its debug build walks 10 steps in minutes.
fn on_virtual_robot(args: &[String]) -> Vec<String> {
    if args[0] == "demo" {
        let mut a = args.to_vec();
        if !a.iter().any(|w| w == "--steps") {
            a.extend(["--steps", "2"].map(str::to_owned));
        }
        return a;
    }
    if on_physics(args) {
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

/// Where an example runs: one test per group (the enum is matched exhaustively, so a new example
/// lands in a group, never nowhere). A walk on the virtual robot takes its simulated time in wall
/// time (10 steps: about 25 s), so each documented walk is a group of its own.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Group {
    /// The README's plans of the built-in models, their comparison, step table and upload.
    Readme,
    /// The README's plans with springs and with the physical robot's preset.
    ReadmeVariants,
    /// The README's run.
    ReadmeWalk,
    /// `dbot compare --paper` (the paper's tables and figures).
    Paper,
    /// docs/usage.md on the virtual robot: model export and the board commands that do not walk.
    Board,
    /// docs/usage.md: `dbot run` forward.
    Walk,
    /// docs/usage.md: `dbot run --backward`.
    WalkBackward,
    /// docs/usage.md: `dbot record --play` (a walk recorded).
    Record,
    /// docs/usage.md: a named trial recorded and compared with its plan.
    Trial,
    /// docs/usage.md on the physics robot.
    Physics,
    /// docs/usage.md: the strain gauges' walk and comparison.
    Strain,
    /// docs/usage.md: the demo on the physics robot.
    Demo,
    /// docs/usage.md: the demo on the virtual robot.
    DemoVirtual,
    /// `dbot validate --check`: run by the `validation_doc` tests.
    Validation,
}

/// Whether the example names the physics robot as its port.
fn on_physics(args: &[String]) -> bool {
    args.windows(2)
        .any(|w| (w[0] == "--port" || w[0] == "-p") && w[1].starts_with("physics"))
}

fn group_of(e: &Example) -> Group {
    let words = e.args.join(" ");
    let has = |w: &str| e.args.iter().any(|a| a == w);
    match e.args[0].as_str() {
        "demo" if words.contains("--port virtual") => Group::DemoVirtual,
        "demo" => Group::Demo,
        "validate" => Group::Validation,
        "compare" if has("--paper") => Group::Paper,
        "run" if e.at.starts_with("README.md") => Group::ReadmeWalk,
        "plan" if e.at.starts_with("README.md") && (has("--spring") || has("--preset")) => {
            Group::ReadmeVariants
        }
        _ if e.at.starts_with("README.md") => Group::Readme,
        _ if on_physics(&e.args) => Group::Physics,
        _ if words.contains("strain") => Group::Strain,
        "run" if has("--backward") => Group::WalkBackward,
        "run" => Group::Walk,
        "record" if has("--trial") => Group::Trial,
        "compare" => Group::Trial,
        "record" => Group::Record,
        _ => Group::Board,
    }
}

/// The documented examples a group runs first because it reads what they write, or needs the
/// gait they upload (words after `dbot`; each must be an example of the documents).
fn needs(group: Group) -> &'static [&'static str] {
    const PLAN: &str = "plan --model drosophibot2 --out out/walk";
    const TABLE: &str = "table --plan out/walk --out gait.dbgt";
    const UPLOAD: &str = "upload --table gait.dbgt --slot 1";
    match group {
        Group::ReadmeWalk => &[
            PLAN,
            "table --plan out/walk --out walk.dbgt",
            "upload --table walk.dbgt --slot 1 --port /dev/ttyACM0",
        ],
        Group::Board => &[PLAN],
        Group::Walk | Group::WalkBackward => &[PLAN, TABLE, UPLOAD],
        Group::Record | Group::Trial | Group::Physics => &[PLAN, TABLE],
        Group::Readme
        | Group::ReadmeVariants
        | Group::Paper
        | Group::Strain
        | Group::Demo
        | Group::DemoVirtual
        | Group::Validation => &[],
    }
}

fn all_examples() -> Vec<Example> {
    let all: Vec<Example> = ["README.md", "docs/usage.md"]
        .iter()
        .flat_map(|f| examples(f))
        .collect();
    assert!(
        all.len() >= 20,
        "found only {} examples: {all:?}",
        all.len()
    );
    all
}

/// Runs the group's examples (after the ones it needs) in a fresh scratch folder, in document
/// order; fails listing every example that failed, with its output. The number of examples run.
fn run_group(group: Group) -> usize {
    let dir = tempfile::tempdir().unwrap();
    let all = all_examples();
    let mut run: Vec<&Example> = needs(group)
        .iter()
        .map(|words| {
            all.iter()
                .find(|e| e.args.join(" ") == *words)
                .unwrap_or_else(|| {
                    panic!("{group:?} needs `dbot {words}`, which no document gives")
                })
        })
        .collect();
    run.extend(
        all.iter()
            .filter(|e| !e.needs_hardware && group_of(e) == group),
    );
    let mut failed = Vec::new();
    for e in &run {
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
    assert!(
        failed.is_empty(),
        "{} failed:\n{}",
        failed.len(),
        failed.join("\n")
    );
    run.len()
}

#[test]
fn the_readmes_commands_run_on_the_virtual_robot() {
    assert!(run_group(Group::Readme) >= 5);
}

#[test]
fn the_readmes_plans_with_springs_and_the_physical_robots_preset_run() {
    assert_eq!(run_group(Group::ReadmeVariants), 2);
}

#[test]
fn the_readmes_walk_runs_on_the_virtual_robot() {
    assert_eq!(run_group(Group::ReadmeWalk), 3 + 1);
}

#[test]
fn the_papers_comparison_runs() {
    assert_eq!(run_group(Group::Paper), 1);
}

#[test]
fn the_board_commands_of_the_usage_guide_run_on_the_virtual_robot() {
    // The plan it needs, then 12 or more of its own.
    assert!(run_group(Group::Board) >= 13);
}

#[test]
fn the_usage_guides_walk_runs_on_the_virtual_robot() {
    assert_eq!(run_group(Group::Walk), 3 + 1);
}

#[test]
fn the_usage_guides_backward_walk_runs_on_the_virtual_robot() {
    assert_eq!(run_group(Group::WalkBackward), 3 + 1);
}

#[test]
fn the_usage_guides_recorded_walk_runs_on_the_virtual_robot() {
    assert_eq!(run_group(Group::Record), 2 + 1);
}

#[test]
fn the_usage_guides_trial_is_recorded_and_compared_on_the_virtual_robot() {
    assert_eq!(run_group(Group::Trial), 2 + 2);
}

#[test]
fn the_usage_guides_walk_on_the_physics_robot_runs() {
    assert!(run_group(Group::Physics) >= 2 + 2);
}

#[test]
fn the_usage_guides_strain_commands_run_on_the_virtual_robot() {
    assert!(run_group(Group::Strain) >= 4);
}

#[test]
fn the_demo_runs_on_the_physics_robot() {
    assert_eq!(run_group(Group::Demo), 1);
}

#[test]
fn the_demo_runs_on_the_virtual_robot() {
    assert_eq!(run_group(Group::DemoVirtual), 1);
}

/// Only what truly needs hardware is not run: recording a walk started elsewhere, and the U2D2
/// examples (a new one must be added here on purpose); and only `dbot validate --check
/// docs/validation.md` is left to `validation_doc`.
#[test]
fn only_hardware_examples_and_the_validation_check_are_not_run_here() {
    let all = all_examples();
    let skipped: Vec<String> = all
        .iter()
        .filter(|e| e.needs_hardware)
        .map(|e| format!("dbot {}", e.args.join(" ")))
        .collect();
    assert_eq!(
        skipped,
        [
            "dbot record --out out/rec --table walk.dbgt --seconds 20 --port /dev/ttyACM0",
            "dbot dxl scan -p /dev/ttyUSB0 --baud auto",
            "dbot set --baud 2000000 --rate 200",
            "dbot record --out rec --table gait.dbgt --seconds 20",
        ],
        "{skipped:?}"
    );
    let elsewhere: Vec<String> = all
        .iter()
        .filter(|e| !e.needs_hardware && group_of(e) == Group::Validation)
        .map(|e| format!("{}: dbot {}", e.at, e.args.join(" ")))
        .collect();
    assert_eq!(elsewhere.len(), 1, "{elsewhere:?}");
    assert!(
        elsewhere[0].ends_with(": dbot validate --check docs/validation.md"),
        "{elsewhere:?}"
    );
}

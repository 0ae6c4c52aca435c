//! The rules that protect the robot are the library's (`board::rules`), so every door refuses
//! alike: the same infeasible plan is refused by `dbot table` and `dbot upload --plan` with the same
//! words, `--allow-infeasible` builds the same bytes through both, and the table file it built is
//! refused by `dbot upload --table` and `dbot run --table` without the override; `dbot run --period` refuses a
//! period at which a servo could not follow the table, naming the joint, the speed and the limit,
//! `dbot record --play --period` refuses it with the same words, and `dbot steer --speed` refuses the speed that asks for that period with the same words;
//! `dbot set --stiffness` refuses what the servos' P gain register cannot hold. The Python doors
//! are python/tests/test_refusals.py.
//!
//! Independent truth: the servos' no-load speeds from the e-manual (MX-28 55 rev/min, MX-64 63
//! rev/min at 12 V), peak speeds computed here from joints.csv's angles by the periodic central
//! difference of the paper's equation 1, and the P gain register's range (1 to 16383) times the
//! e-manual's P gain scaling.

use crate::cli_support;
use std::f64::consts::TAU;
use std::path::Path;
use std::process::Output;

use cli_support::in_dir;

fn dbot(dir: &Path, args: &[&str]) -> Output {
    in_dir(dir)
        .args(args)
        .env("RUST_BACKTRACE", "0")
        .output()
        .unwrap()
}

/// `args` on the virtual robot whose flash is `robot.flash` in `dir`.
fn on_robot(dir: &Path, args: &[&str]) -> Output {
    let port = format!("virtual:{}", dir.join("robot.flash").display());
    let mut all = args.to_vec();
    all.extend(["--port", &port, "--create"]);
    dbot(dir, &all)
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn ok(o: Output) -> String {
    assert!(o.status.success(), "{}{}", stdout(&o), stderr(&o));
    stdout(&o)
}

/// The refusal a failed command printed: its `Error: ` text.
fn refusal(o: &Output) -> String {
    assert!(!o.status.success(), "was not refused: {}", stdout(o));
    let e = stderr(o);
    e.strip_prefix("Error: ")
        .unwrap_or_else(|| panic!("no error line: {e}"))
        .trim_end()
        .to_owned()
}

/// The folders in `out`, trials and partial ones (beside the index files).
fn trial_folders(out: &Path) -> Vec<String> {
    std::fs::read_dir(out)
        .unwrap()
        .map(|e| e.unwrap())
        .filter(|e| e.file_type().unwrap().is_dir())
        .map(|e| e.file_name().into_string().unwrap())
        .collect()
}

/// No-load speeds at 12 V, rad/s, from the e-manuals' rev/min.
const MX28_NO_LOAD: f64 = 55.0 * TAU / 60.0;

/// Angles of `joint` per slice from a plan directory's joints.csv (parsed here, not by the planner).
fn angles(plan: &Path, joint: &str) -> Vec<f64> {
    let mut r = csv::Reader::from_path(plan.join("joints.csv")).unwrap();
    let h = r.headers().unwrap().clone();
    let col = |name: &str| h.iter().position(|c| c == name).unwrap();
    let (leg, jn, angle) = (col("leg"), col("joint"), col("angle_rad"));
    let (want_leg, want_joint) = joint.split_once('_').unwrap();
    r.records()
        .map(|rec| rec.unwrap())
        .filter(|rec| &rec[leg] == want_leg && &rec[jn] == want_joint)
        .map(|rec| rec[angle].parse().unwrap())
        .collect()
}

/// Peak |dq/dt| over a periodic cycle of slices `dt` apart, by central differences (equation 1).
fn peak_speed(q: &[f64], dt: f64) -> f64 {
    let n = q.len();
    (0..n)
        .map(|s| ((q[(s + 1) % n] - q[(s + n - 1) % n]) / (2.0 * dt)).abs())
        .fold(0.0, f64::max)
}

/// The speed (rad/s) the refusal line of `joint` names.
fn named_speed(text: &str, joint: &str) -> f64 {
    let line = text
        .lines()
        .find(|l| l.trim_start().starts_with(&format!("{joint} at slice")))
        .unwrap_or_else(|| panic!("{joint} not named: {text}"));
    line.split(": ")
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

#[test]
fn table_and_upload_refuse_the_same_infeasible_plan_with_the_same_words() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The original solver's 0.5 s swing (table 1, 1.25 s per step): too fast for the front FTi.
    ok(dbot(
        d,
        &["plan", "--preset", "table1", "--out", "p", "--slices", "50"],
    ));
    let by_table = refusal(&dbot(d, &["table", "--plan", "p", "--out", "t.dbgt"]));
    let by_upload = refusal(&on_robot(d, &["upload", "--plan", "p", "--slot", "3"]));
    assert_eq!(by_table, by_upload);
    assert!(
        by_table.starts_with("plan p: the servos cannot follow this plan:\n"),
        "{by_table}"
    );
    assert!(
        by_table.ends_with("--allow-infeasible (Python: allow_infeasible=True) to build it anyway")
    );
    // The speed named is the peak of the angles in joints.csv, against 55 rev/min.
    let q = angles(&d.join("p"), "LF_FTi");
    let peak = peak_speed(&q, 1.25 / 50.0);
    assert!(peak > MX28_NO_LOAD, "{peak}");
    assert!(
        (named_speed(&by_table, "LF_FTi") - peak).abs() < 0.006,
        "{peak}: {by_table}"
    );
    assert!(
        by_table.contains(&format!("no-load speed {MX28_NO_LOAD:.2} rad/s")),
        "{by_table}"
    );
    // Nothing was written or stored.
    assert!(!d.join("t.dbgt").exists());
    assert!(ok(on_robot(d, &["gaits"])).contains("slot 3: empty"));

    // The override: the same bytes through both doors, each warning in the library's words.
    let o = dbot(
        d,
        &[
            "table",
            "--plan",
            "p",
            "--out",
            "t.dbgt",
            "--allow-infeasible",
        ],
    );
    let warned_table = stderr(&o);
    ok(o);
    let o = on_robot(
        d,
        &["upload", "--plan", "p", "--slot", "3", "--allow-infeasible"],
    );
    let warned_upload = stderr(&o);
    let out = ok(o);
    assert_eq!(warned_table, warned_upload);
    let list = by_table
        .split_once('\n')
        .unwrap()
        .1
        .rsplit_once('\n')
        .unwrap()
        .0;
    assert_eq!(
        warned_table.trim_end(),
        format!(
            "warning: plan p: the servos cannot follow this plan (--allow-infeasible / allow_infeasible=True):\n{list}"
        )
    );
    let bytes = std::fs::read(d.join("t.dbgt")).unwrap();
    let crc = protocol::GaitTable::parse(&bytes).unwrap().crc();
    assert!(out.contains(&format!("CRC {crc:#010x} read back")), "{out}");

    // The table file built with the override meets the rule again at every door that takes a
    // file (it used to upload and play unchecked): refused without the override, naming the
    // same joint, and nothing stored.
    let first = |t: &str| t.lines().next().unwrap_or("").to_owned();
    let by_file = refusal(&on_robot(
        d,
        &["upload", "--table", "t.dbgt", "--slot", "2"],
    ));
    assert_eq!(
        first(&by_file),
        "step table t.dbgt: the servos cannot follow this plan:",
        "{by_file}"
    );
    assert!(by_file.contains("  LF_FTi at slice"), "{by_file}");
    let by_run = refusal(&on_robot(
        d,
        &["run", "--table", "t.dbgt", "--slot", "2", "--steps", "1"],
    ));
    assert_eq!(first(&by_run), first(&by_file), "{by_run}");
    assert!(ok(on_robot(d, &["gaits"])).contains("slot 2: empty"));
    let o = on_robot(
        d,
        &[
            "upload",
            "--table",
            "t.dbgt",
            "--slot",
            "2",
            "--allow-infeasible",
        ],
    );
    let warned_file = stderr(&o);
    ok(o);
    assert!(
        warned_file.starts_with(
            "warning: step table t.dbgt: the servos cannot follow this plan (--allow-infeasible / allow_infeasible=True):\n"
        ),
        "{warned_file}"
    );
}

#[test]
fn a_period_the_servos_cannot_follow_is_refused_naming_joint_speed_and_limit() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The default preset (servo-safe: 1.0 s swing, 2.5 s per step) is feasible as planned.
    ok(dbot(d, &["plan", "--out", "p", "--slices", "50"]));
    ok(on_robot(d, &["upload", "--plan", "p", "--slot", "1"]));
    let q = angles(&d.join("p"), "LF_FTi");
    let planned = peak_speed(&q, 2.5 / 50.0);
    assert!(planned < MX28_NO_LOAD, "{planned}");
    // 1.0 s per step is 0.4 times the planned period: every speed 2.5 times the planned one.
    let refused = refusal(&on_robot(
        d,
        &["run", "--slot", "1", "--steps", "1", "--period", "1.0"],
    ));
    assert!(
        refused.starts_with(
            "slot 1 (\"p\"): at 1.000 s per step (0.400 times the planned 2.500 s) the servos cannot follow it:\n"
        ),
        "{refused}"
    );
    let scaled = planned * 2.5;
    assert!(scaled > MX28_NO_LOAD, "{scaled}");
    // Table angles are kept to 1e-4 rad: 1e-4 / (2 x 0.02 s) = 0.0025 rad/s at most.
    let named = named_speed(&refused, "LF_FTi");
    assert!(
        (named - scaled).abs() < 0.008,
        "{named} vs {scaled}: {refused}"
    );
    assert!(
        refused.contains(&format!(
            "over the servo's no-load speed {MX28_NO_LOAD:.2} rad/s"
        )),
        "{refused}"
    );
    // `dbot record --play` starts its walk through the same rule: the same words, and no trial.
    let record = |extra: &[&str]| {
        let mut args = vec![
            "record", "--out", "trials", "--play", "1", "--steps", "1", "--period", "1.0",
        ];
        args.extend(extra);
        on_robot(d, &args)
    };
    assert_eq!(refusal(&record(&[])), refused);
    assert!(!d.join("trials").exists() || trial_folders(&d.join("trials")).is_empty());
    // Nothing was played: the board never left standing still.
    assert!(
        !ok(on_robot(d, &["status"])).contains("Walking"),
        "walked after a refusal"
    );
    let o = record(&["--allow-infeasible"]);
    let warned = stderr(&o);
    ok(o);
    assert!(
        warned.starts_with("warning: slot 1 (\"p\"): the servos cannot follow this plan"),
        "{warned}"
    );
    assert_eq!(trial_folders(&d.join("trials")).len(), 1);
    // Slower than planned needs no check; the override plays the fast one with a warning.
    ok(on_robot(
        d,
        &["run", "--slot", "1", "--steps", "1", "--period", "3.0"],
    ));
    let o = on_robot(
        d,
        &[
            "run",
            "--slot",
            "1",
            "--steps",
            "1",
            "--period",
            "1.0",
            "--allow-infeasible",
        ],
    );
    let warned = stderr(&o);
    ok(o);
    assert!(
        warned.starts_with("warning: slot 1 (\"p\"): the servos cannot follow this plan"),
        "{warned}"
    );
}

#[test]
fn a_steering_speed_the_servos_cannot_follow_is_refused_as_run_period() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(dbot(d, &["plan", "--out", "p", "--slices", "50"]));
    ok(on_robot(d, &["upload", "--plan", "p", "--slot", "1"]));
    let steer = |speed: &str, extra: &[&str]| {
        let mut args = vec![
            "steer",
            "--family",
            "1,1,1",
            "--range",
            "0.06",
            "--heading",
            "0",
            "--speed",
            speed,
            "--steps",
            "1",
        ];
        args.extend(extra);
        on_robot(d, &args)
    };
    // Speed 2.5 plays the table at 1 / 2.5 = 0.4 times its period: 1.0 s per step, the period
    // `run --period 1.0` is refused at, so the same lines follow the speed named.
    let by_run = refusal(&on_robot(
        d,
        &["run", "--slot", "1", "--steps", "1", "--period", "1.0"],
    ));
    let by_steer = refusal(&steer("2.5", &[]));
    assert_eq!(by_steer, format!("steering at speed 2.5: {by_run}"));
    let q = angles(&d.join("p"), "LF_FTi");
    let scaled = peak_speed(&q, 2.5 / 50.0) * 2.5;
    assert!(scaled > MX28_NO_LOAD, "{scaled}");
    assert!(
        (named_speed(&by_steer, "LF_FTi") - scaled).abs() < 0.008,
        "{scaled}: {by_steer}"
    );
    assert!(
        !ok(on_robot(d, &["status"])).contains("Walking"),
        "walked after a refusal"
    );
    // As planned it walks; the override walks the fast one, warning in the library's words.
    ok(steer("1", &[]));
    let o = steer("2.5", &["--allow-infeasible"]);
    let warned = stderr(&o);
    assert!(ok(o).contains("1 step(s), the robot stands"));
    assert!(
        warned.starts_with(
            "warning: steering at speed 2.5: slot 1 (\"p\"): the servos cannot follow this plan"
        ),
        "{warned}"
    );
}

#[test]
fn a_stiffness_the_p_gain_register_cannot_hold_is_refused_with_the_limit() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // MX-28: P gain / 128 of the 885 PWM units at stall torque 2.5 N m per tick (2 pi / 4096 rad)
    // is 0.014387 N m/rad per unit; the register holds at most 16383: 235.70 N m/rad. MX-64: 6.0 N m,
    // 0.034529 per unit, so below half a unit (0.01726 N m/rad) its nearest gain is 0.
    let unit28 = 1.0 / 128.0 / 885.0 * 2.5 * 4096.0 / TAU;
    let max28 = 16383.0 * unit28;
    let half64 = unit28 * 6.0 / 2.5 / 2.0;
    assert!((max28 - 235.70).abs() < 0.01 && (half64 - 0.01726).abs() < 1e-5);
    let over = refusal(&on_robot(d, &["set", "--stiffness", "240"]));
    assert!(
        over.contains(&format!(
            "--stiffness 240: stiffness 240 N m/rad is more than the MX-28(2.0)'s Position P Gain register holds: at most {max28:.1} N m/rad"
        )),
        "{over}"
    );
    assert!(
        over.contains("while the torque bias divided by 240"),
        "{over}"
    );
    let under = refusal(&on_robot(d, &["set", "--stiffness", "0.01"]));
    assert!(
        under.contains("MX-64(2.0)")
            && under.contains(&format!("give at least {half64:.4} N m/rad")),
        "{under}"
    );
    // Within the register on both servos the board takes it (after a gait gave it joints).
    ok(dbot(d, &["plan", "--out", "p", "--slices", "50"]));
    ok(on_robot(d, &["upload", "--plan", "p", "--slot", "0"]));
    ok(on_robot(d, &["run", "--slot", "0", "--steps", "1"]));
    let out = ok(on_robot(d, &["set", "--stiffness", "235"]));
    assert!(out.contains("stiffness 235 N m/rad"), "{out}");
    // 0 is the firmware's "bias off" (as docs/usage.md says), not a register value.
    let out = ok(on_robot(d, &["set", "--stiffness", "0"]));
    assert!(out.contains("torque bias off"), "{out}");
}

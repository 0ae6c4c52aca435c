//! `dbot record --strain` (issue 26 item 4) against `dbot sim-strain` on a pseudo-terminal and
//! the virtual robot: the strain board unplugged or garbling a line mid-recording costs the
//! servo recording nothing (its CSV has exactly the rows of the same walk recorded without
//! strain: the virtual robot runs on simulated time, so the same walk gives the same cycles), the
//! trial says strain yes, and the servo board's own port is refused as the strain port by name.

use crate::board_fakes;
use crate::cli_support;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use cli_support::Server;

use board::trial::{latest_trial, read_trial};
use board_fakes::cli::{record_args, run, strings, table};

/// Starts `dbot sim-strain` with `faults` on `link` and waits for the link to appear.
fn sim_strain(faults: &[&str], link: &Path) -> Server {
    let mut c = Command::new(env!("CARGO_BIN_EXE_dbot"));
    c.arg("sim-strain");
    for f in faults {
        c.args(["--fault", f]);
    }
    c.arg("--link").arg(link);
    cli_support::serve(c, &[link], Duration::from_secs(60), "sim-strain")
}

fn record(dir: &Path, out: &Path, t: &str, extra: &[&str]) -> board_fakes::cli::Done {
    let mut a = record_args(out, t, "virtual", &["--steps", "3"]);
    a.extend(strings(extra));
    run(dir, &a)
}

/// The rows of the same walk recorded without strain.
fn rows_without_strain(dir: &Path, t: &str) -> usize {
    let out = dir.join("plain");
    let d = record(dir, &out, t, &[]);
    assert!(d.status.success(), "{}{}", d.stdout, d.stderr);
    read_trial(&latest_trial(&out).unwrap().unwrap())
        .unwrap()
        .rows
        .len()
}

fn strain_rows(trial: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(trial.join("strain.csv")).unwrap();
    text.lines().map(str::to_owned).collect()
}

fn faulty_recording(fault: &str) -> (board_fakes::cli::Done, PathBuf, usize, tempfile::TempDir) {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().to_owned();
    // 3 steps of 2 s: 6 s of simulated walking, long after the strain fault's few samples.
    let t = table(&dir, "g.dbgt", 40, 2.0);
    let plain = rows_without_strain(&dir, &t);
    let link = dir.join("strain");
    let _s = sim_strain(&[fault], &link);
    let out = dir.join("trials");
    let d = record(&dir, &out, &t, &["--strain", link.to_str().unwrap()]);
    let trial = latest_trial(&out).unwrap().expect("the trial is kept");
    (d, trial, plain, tmp)
}

#[test]
fn a_strain_board_unplugged_mid_recording_leaves_the_servo_recording_whole() {
    let (d, trial, plain, _tmp) = faulty_recording("hangup-at:4");
    assert!(!d.status.success(), "{}", d.stdout);
    assert!(
        d.stderr
            .contains("the servo recording is complete in the trial"),
        "{}",
        d.stderr
    );
    assert!(
        d.stderr
            .contains("strain board went away (unplugged?) after 4 samples; 4 samples kept in"),
        "{}",
        d.stderr
    );
    let tr = read_trial(&trial).unwrap();
    assert_eq!(tr.rows.len(), plain);
    assert_eq!(tr.meta.outcome, board::trial::Outcome::Complete);
    assert!(tr.meta.strain);
    let rows = strain_rows(&trial);
    assert!(
        rows[0].starts_with("time_s,host_s,LH_troch_axial,"),
        "{}",
        rows[0]
    );
    // The header and the four samples the board sent, each aligned (a board time in `time_s`).
    assert_eq!(rows.len(), 5, "{rows:?}");
    for r in &rows[1..] {
        let t: f64 = r.split(',').next().unwrap().parse().unwrap();
        assert!(t.is_finite(), "{r}");
    }
    let readme = std::fs::read_to_string(trial.join("README.md")).unwrap();
    assert!(readme.contains("- strain recorded: yes"), "{readme}");
}

#[test]
fn a_garbled_strain_line_names_its_gauge_and_costs_the_servos_nothing() {
    let (d, trial, plain, _tmp) = faulty_recording("garbage-at:3");
    assert!(!d.status.success(), "{}", d.stdout);
    // The eighth value of a line is board leg 1 (RH), gauge 1 (trochanter transverse).
    assert!(
        d.stderr.contains("column 8, RH_troch_transverse"),
        "{}",
        d.stderr
    );
    assert!(
        d.stderr.contains("`3?0.00` is not a number"),
        "{}",
        d.stderr
    );
    assert_eq!(read_trial(&trial).unwrap().rows.len(), plain);
    assert_eq!(strain_rows(&trial).len(), 4);
}

#[test]
fn the_servo_boards_port_is_refused_as_the_strain_port() {
    let dir = tempfile::tempdir().unwrap();
    let t = table(dir.path(), "g.dbgt", 40, 0.4);
    let port = dir.path().join("ttyACM0");
    let p = port.to_str().unwrap();
    let out = dir.path().join("trials");
    let d = run(dir.path(), &record_args(&out, &t, p, &["--strain", p]));
    assert!(!d.status.success());
    assert!(
        d.stderr.contains(&format!("strain board {p}\n"))
            && d.stderr.contains(&format!(
                "{p} is the servo board's port; the strain board has a port of its own"
            )),
        "{}",
        d.stderr
    );
    // Refused before anything was opened or made: no trial folder.
    assert!(!out.exists());
}

/// `dbot compare --strain` on a recording of the in-process strain board, which reads its
/// baseline whatever the robot does: no strain measured, so every gauge's fitted gain is 0
/// counts per microstrain (and no R^2: the counts do not vary), for the gauges the plan predicts.
#[test]
fn compare_fits_a_zero_gain_to_a_board_that_measures_no_strain() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let plan = dir.join("p");
    let p = plan.to_str().unwrap();
    let d = run(dir, &strings(&["plan", "--slices", "20", "--out", p]));
    assert!(d.status.success(), "{}", d.stderr);
    let t = plan.join("walk.dbgt");
    let t = t.to_str().unwrap();
    let d = run(dir, &strings(&["table", "--plan", p, "--out", t]));
    assert!(d.status.success(), "{}", d.stderr);
    let out = dir.join("trials");
    let d = record(dir, &out, t, &["--strain", "virtual"]);
    assert!(d.status.success(), "{}{}", d.stdout, d.stderr);
    let trial = latest_trial(&out).unwrap().unwrap();
    let cmp = dir.join("cmp");
    let d = run(
        dir,
        &strings(&[
            "compare",
            "--strain",
            trial.to_str().unwrap(),
            p,
            "--out",
            cmp.to_str().unwrap(),
        ]),
    );
    assert!(d.status.success(), "{}{}", d.stdout, d.stderr);
    let gains = std::fs::read_to_string(cmp.join("strain_gains.csv")).unwrap();
    let lines: Vec<&str> = gains.lines().collect();
    assert_eq!(lines[0], "gauge,counts_per_microstrain,r2,samples");
    // The built-in model predicts all 36 of the board's gauges.
    assert_eq!(lines.len(), 37, "{gauges}", gauges = gains);
    for l in &lines[1..] {
        let c: Vec<&str> = l.split(',').collect();
        let samples: usize = c[3].parse().unwrap();
        assert!(samples > 0, "{l}");
        assert_eq!((c[1], c[2]), ("0.000000", ""), "{l}");
    }
    // Without a calibration every gauge is read through the ESTIMATE gain; with the plan's model
    // naming one, the gauge it has is read through it, and the table says so per gauge.
    let line = |out: &str, gauge: &str| {
        out.lines()
            .find(|l| l.starts_with(&format!("| {gauge} |")))
            .unwrap_or_else(|| panic!("no {gauge} in\n{out}"))
            .to_owned()
    };
    assert!(line(&d.stdout, "LF_troch_axial").contains("ESTIMATE (0.5000 counts per microstrain)"));
    std::fs::write(
        plan.join("cal.toml"),
        "[gauge.LF_troch_axial]\ncounts_per_microstrain = 0.25\n",
    )
    .unwrap();
    let model_toml = plan.join("model.toml");
    let text = std::fs::read_to_string(&model_toml).unwrap();
    std::fs::write(&model_toml, format!("calibration = \"cal.toml\"\n{text}")).unwrap();
    let args = ["compare", "--strain", trial.to_str().unwrap(), p, "--out"];
    let d = run(
        dir,
        &strings(&[&args[..], &[cmp.to_str().unwrap()]].concat()),
    );
    assert!(d.status.success(), "{}{}", d.stdout, d.stderr);
    assert!(
        line(&d.stdout, "LF_troch_axial").contains("calibrated (0.2500 counts per microstrain)")
    );
    assert!(line(&d.stdout, "LF_femur_axial").contains("ESTIMATE (0.5000 counts per microstrain)"));
    // One plan directory, not two, with --strain.
    let d = run(
        dir,
        &strings(&["compare", "--strain", trial.to_str().unwrap(), p, p]),
    );
    assert!(
        d.stderr
            .contains("--strain TRIAL compares with one plan directory"),
        "{}",
        d.stderr
    );
}

/// `--port physics --strain virtual`: the in-process strain board reads the body's simulated
/// gauges (counts = 300 + 0.5 x microstrain, saturating at 0..1023). Its first sample, the
/// baseline, is taken before gravity ramps in (the physics robot powers on weightless), so it is
/// the 300 counts calibration trimmed to; once the body stands on its legs the gauges move off it
/// by far more than the 1-count ADC step (the standing prediction reaches 470 microstrain, 235
/// counts, `physics/tests/integration/strain_standing.rs`).
#[test]
fn the_physics_robots_gauges_feed_the_virtual_strain_board() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // The planned tripod: a gait the physics robot's servos can follow (the synthetic table's
    // swings are not planned for this body, and a servo that cannot follow ends the trial as
    // faulted, not complete).
    let t = dir.join("walk.dbgt");
    std::fs::write(&t, lab::walk::tripod_table().unwrap()).unwrap();
    let t = t.display().to_string();
    let out = dir.join("trials");
    let d = run(
        dir,
        &record_args(
            &out,
            &t,
            "physics",
            &["--steps", "1", "--strain", "virtual"],
        ),
    );
    assert!(d.status.success(), "{}{}", d.stdout, d.stderr);
    let trial = latest_trial(&out).unwrap().unwrap();
    let base = std::fs::read_to_string(trial.join("strain_baseline.csv")).unwrap();
    let row: Vec<&str> = base.lines().nth(1).unwrap().split(',').collect();
    assert_eq!(row[0], "first_sample");
    assert!(row[1..].iter().all(|v| *v == "300"), "{base}");
    let rows = strain_rows(&trial);
    let mut largest = 0.0f64;
    for r in &rows[1..] {
        for v in r.split(',').skip(2) {
            let c: f64 = v.parse().unwrap();
            assert!((0.0..=1023.0).contains(&c), "{r}");
            largest = largest.max((c - 300.0).abs());
        }
    }
    assert!(largest > 50.0, "largest deviation {largest} counts");
}

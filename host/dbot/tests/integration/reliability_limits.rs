//! Hostile numbers (issue #19, items 4 to 6), run as processes (the real `CARGO_BIN_EXE_dbot`):
//! absurd model values, friction coefficients and board settings are refused naming the field
//! and the limit, a plan or a comparison never reports NaN with exit 0, and a plan's size is
//! bounded by what a gait slot holds. The board settings are checked before any port is opened
//! (the port given does not exist and must not be named).

use crate::board_fakes;
use std::path::Path;

use board_fakes::cli::{fails_naming, run, strings};

const NO_PORT: &str = "/dev/does-not-exist";

fn model_toml() -> String {
    std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../planner/models/drosophibot2.toml"
    ))
    .unwrap()
}

/// The robot's model with the first line starting `key =` set to `value`, written to `dir`.
fn model_with(dir: &Path, name: &str, key: &str, value: &str) -> String {
    let text = model_toml();
    let mut done = false;
    let out: Vec<String> = text
        .lines()
        .map(|l| {
            if !done && l.trim_start().starts_with(&format!("{key} =")) {
                done = true;
                format!("{key} = {value}")
            } else {
                l.to_owned()
            }
        })
        .collect();
    assert!(done, "no `{key} =` line in drosophibot2.toml");
    let p = dir.join(name);
    std::fs::write(&p, out.join("\n")).unwrap();
    p.display().to_string()
}

fn plan(dir: &Path, args: &[&str]) -> board_fakes::cli::Done {
    let out = dir.join("plan").display().to_string();
    let mut a = strings(&["plan", "--out", &out]);
    a.extend(strings(args));
    run(dir, &a)
}

#[test]
fn absurd_model_numbers_are_refused_naming_the_field() {
    let dir = tempfile::tempdir().unwrap();
    // Before: mass -2567 was refused by the TOML reader, but 1e30 kg planned, and a stiffness
    // of 1e-300 failed later as a "singular pose".
    for (key, value, needles) in [
        (
            "mass_kg",
            "1e30",
            &["body", "mass", "1000000000000000000000000000000 kg"][..],
        ),
        ("mass_kg", "nan", &["body", "mass", "NaN"][..]),
        (
            "stiffness_nm_per_rad",
            "1e-300",
            &["joint", "stiffness", "1e-300"][..],
        ),
        ("stiffness_nm_per_rad", "inf", &["joint", "stiffness"][..]),
    ] {
        let m = model_with(dir.path(), "m.toml", key, value);
        let d = plan(dir.path(), &["--model", &m, "--no-dynamics"]);
        let mut n = needles.to_vec();
        n.push("m.toml");
        fails_naming(&d, &format!("{key} = {value}"), &n);
        assert!(!dir.path().join("plan").exists());
    }
}

#[test]
fn absurd_aproj_masses_and_sizes_are_refused_naming_the_field() {
    let source = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/models/animatlab/Drosobot2.aproj"
    );
    let text = std::fs::read_to_string(source)
        .unwrap_or_else(|e| panic!("{source}: {e} (the shared models are needed here)"));
    let dir = tempfile::tempdir().unwrap();
    // Before: each of these planned, with 1920 NaN torques and "peak 0.308 N m", exit 0.
    for (from, to, field) in [
        (r#"<Mass Value="2567""#, r#"<Mass Value="-2567""#, "Mass"),
        (r#"<Mass Value="2567""#, r#"<Mass Value="NaN""#, "Mass"),
        (r#"<Mass Value="2567""#, r#"<Mass Value="1e400""#, "Mass"),
        (r#"<Mass Value="2567""#, r#"<Mass Value="1e30""#, "Mass"),
    ] {
        assert!(text.contains(from));
        let p = dir.path().join("bad.aproj");
        std::fs::write(&p, text.replacen(from, to, 1)).unwrap();
        let d = plan(dir.path(), &["--model", p.to_str().unwrap()]);
        fails_naming(&d, to, &["bad.aproj", field]);
    }
}

#[test]
fn a_friction_coefficient_that_is_no_number_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    // Before: "0 foot-slices outside the mu = NaN cone", exit 0.
    for mu in ["nan", "-1", "0", "inf"] {
        let d = plan(dir.path(), &[&format!("--mu={mu}"), "--slices", "8"]);
        fails_naming(&d, &format!("--mu {mu}"), &["--mu", "friction"]);
    }
}

#[test]
fn compare_against_a_plan_with_nan_is_refused_naming_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = plan(dir.path(), &["--slices", "8"]);
    assert!(d.status.success(), "{}", d.stderr);
    let a = dir.path().join("plan");
    let b = dir.path().join("nan");
    std::fs::create_dir(&b).unwrap();
    // One torque of the copy replaced by NaN (the last field of the first data row that has one).
    let csv = std::fs::read_to_string(a.join("joints.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let col = header.iter().position(|h| *h == "torque_nm").unwrap();
    let mut lines: Vec<String> = csv.lines().map(str::to_owned).collect();
    let mut f: Vec<String> = lines[1].split(',').map(str::to_owned).collect();
    f[col] = "NaN".into();
    lines[1] = f.join(",");
    std::fs::write(b.join("joints.csv"), lines.join("\n") + "\n").unwrap();
    for f in ["plan.json", "model.toml", "feet.csv"] {
        std::fs::copy(a.join(f), b.join(f)).unwrap();
    }
    let out = dir.path().join("cmp").display().to_string();
    let d = run(
        dir.path(),
        &strings(&[
            "compare",
            a.to_str().unwrap(),
            b.to_str().unwrap(),
            "--out",
            &out,
        ]),
    );
    // Before: R^2 = NaN printed, exit 0.
    fails_naming(
        &d,
        "compare with NaN",
        &["joints.csv line 2", "NaN", "finite"],
    );
}

#[test]
fn board_settings_beyond_the_hardware_are_refused_naming_the_limit() {
    let dir = tempfile::tempdir().unwrap();
    // Before: 1e-9 rounded to 0 (torque bias off) and 1e6 were accepted (the port was opened),
    // 12345 bit/s and 1000 Hz at 57 600 bit/s too.
    for (flags, needles) in [
        (
            &["--stiffness", "1e-9"][..],
            &["--stiffness", "0.0005", "rounds to 0"][..],
        ),
        (&["--stiffness", "1e6"][..], &["--stiffness", "3911"][..]),
        (&["--baud", "12345"][..], &["--baud", "12345", "MX"][..]),
        (
            &["--rate", "1000", "--baud", "57600"][..],
            &["57600", "at most 9 Hz"][..],
        ),
        (
            &["--rate", "200", "--baud", "1000000"][..],
            &["at most 160 Hz"][..],
        ),
    ] {
        let mut a = strings(&["set", "--port", NO_PORT]);
        a.extend(strings(flags));
        let d = run(dir.path(), &a);
        fails_naming(&d, &format!("set {flags:?}"), needles);
        assert!(!d.stderr.contains(NO_PORT), "opened the port: {}", d.stderr);
    }
    // The setup file has the same limits (before: 4000 N m/rad there, "at most 4294" for the
    // flag, about 4.3 million accepted by the board; any baud from 9600 to 4.5 M).
    for (text, needles) in [
        ("baud = 12345\n", &["dbot.toml", "baud = 12345"][..]),
        (
            "stiffness = 3999.0\n",
            &["dbot.toml", "stiffness", "3911"][..],
        ),
        (
            "baud = 57600\nrate = 100\n",
            &["dbot.toml", "rate = 100", "at most 9 Hz"][..],
        ),
    ] {
        let cfg = dir.path().join("dbot.toml");
        std::fs::write(&cfg, text).unwrap();
        let d = run(
            dir.path(),
            &strings(&[
                "set",
                "--from-config",
                "--config",
                cfg.to_str().unwrap(),
                "--port",
                NO_PORT,
            ]),
        );
        fails_naming(&d, text, needles);
        assert!(!d.stderr.contains(NO_PORT), "opened the port: {}", d.stderr);
    }
}

#[test]
fn a_plan_bigger_than_a_gait_slot_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    // Before: planned (and `--slices 10000000` grew to the machine's whole memory).
    // By hand: a slot is one of 2 x 4 banks of the 1.5 MiB gait store (196 608 bytes) less its
    // 256-byte record header = 196 352 bytes; a table of the robot's 22 actuated joints takes
    // 36 + 22 x 16 + 4 = 392 bytes plus 2 + 22 x 4 = 90 per slice: (196 352 - 392) / 90 = 2177.
    let d = plan(dir.path(), &["--slices", "5000", "--no-dynamics"]);
    fails_naming(
        &d,
        "--slices 5000",
        &["slices 5000", "at most 2177", "gait slot"],
    );
    assert!(!dir.path().join("plan").exists());
    let d = plan(dir.path(), &["--slices", "10000000", "--no-dynamics"]);
    fails_naming(&d, "--slices 10000000", &["at most 2177"]);
    let d = plan(dir.path(), &["--slices", "2178", "--no-dynamics"]);
    fails_naming(&d, "--slices 2178", &["at most 2177"]);
}

#[test]
fn a_long_plan_says_what_it_is_doing() {
    let dir = tempfile::tempdir().unwrap();
    let d = plan(dir.path(), &["--slices", "600", "--no-dynamics"]);
    assert!(d.status.success(), "{}", d.stderr);
    // Before: nothing on stderr when not on a terminal (the bar hides itself).
    assert!(d.stderr.contains("planning 600 slices"), "{}", d.stderr);
}

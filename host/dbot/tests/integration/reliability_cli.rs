//! Host robustness of every `dbot` command: missing files, unreadable or wrong ports, bad
//! parameters and interrupted runs give a clear message naming the problem and a non-zero exit,
//! and never leave a half-written output file in place of a good one.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn dbot(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_dbot"))
        .args(args)
        .stdin(Stdio::null())
        .output()
        .unwrap()
}

/// Asserts a failure whose stderr names every one of `needles`, and no panic.
fn fails_naming(o: &Output, needles: &[&str]) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "succeeded; stderr: {err}");
    assert_ne!(o.status.code(), Some(101), "panicked: {err}");
    assert!(!err.contains("panicked"), "panicked: {err}");
    for n in needles {
        assert!(err.contains(n), "stderr does not name `{n}`: {err}");
    }
}

/// Every regular file in `dir` with its bytes.
fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap())
        .filter(|e| e.file_type().unwrap().is_file())
        .map(|e| {
            (
                e.file_name().to_string_lossy().into_owned(),
                std::fs::read(e.path()).unwrap(),
            )
        })
        .collect()
}

const PLAN_A: &[&str] = &[
    "--model",
    "drosophibot2",
    "--slices",
    "40",
    "--swing",
    "0.5",
];
const PLAN_B: &[&str] = &[
    "--model",
    "drosophibot2",
    "--slices",
    "48",
    "--swing",
    "0.6",
];

fn plan_into(dir: &Path, params: &[&str]) -> Output {
    let mut args = vec!["plan"];
    args.extend_from_slice(params);
    args.extend(["--out", dir.to_str().unwrap()]);
    dbot(&args)
}

#[test]
fn plan_on_missing_or_bad_inputs_names_the_file_and_field() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let out_s = out.to_str().unwrap();
    let missing = dir.path().join("nope.toml");
    fails_naming(
        &dbot(&["plan", "--model", missing.to_str().unwrap(), "--out", out_s]),
        &["nope.toml"],
    );
    fails_naming(
        &dbot(&["plan", "--model", "no-such-robot", "--out", out_s]),
        &["no-such-robot"],
    );
    fails_naming(
        &dbot(&[
            "plan",
            "--params",
            missing.to_str().unwrap(),
            "--out",
            out_s,
        ]),
        &["nope.toml"],
    );
    let params = dir.path().join("p.toml");
    std::fs::write(&params, "swing_s = 0.5\nduty = 1.5\n").unwrap();
    fails_naming(
        &dbot(&["plan", "--params", params.to_str().unwrap(), "--out", out_s]),
        &["duty"],
    );
    std::fs::write(&params, "swing_s = 0.5\nwobble = 3\n").unwrap();
    fails_naming(
        &dbot(&["plan", "--params", params.to_str().unwrap(), "--out", out_s]),
        &["p.toml", "wobble"],
    );
    let aproj = dir.path().join("broken.aproj");
    std::fs::write(&aproj, "<Project><Organism>").unwrap();
    fails_naming(
        &dbot(&["plan", "--model", aproj.to_str().unwrap(), "--out", out_s]),
        &["broken.aproj"],
    );
    // Nothing was written for any of these.
    assert!(!out.exists());
}

#[test]
fn plan_into_an_unwritable_place_fails_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("a-file");
    std::fs::write(&file, "keep me").unwrap();
    fails_naming(&plan_into(&file, PLAN_A), &["a-file"]);
    assert_eq!(std::fs::read(&file).unwrap(), b"keep me");
}

#[test]
fn a_plan_that_fails_half_way_leaves_the_previous_outputs_whole() {
    // A good plan, then a second one into the same directory that fails at its last output
    // (feet.png is a directory): every file is the old one or a complete new one.
    let dir = tempfile::tempdir().unwrap();
    let o = plan_into(dir.path(), PLAN_A);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let old = snapshot(dir.path());
    let fresh = tempfile::tempdir().unwrap();
    assert!(plan_into(fresh.path(), PLAN_B).status.success());
    let new = snapshot(fresh.path());
    std::fs::remove_file(dir.path().join("feet.png")).unwrap();
    std::fs::create_dir(dir.path().join("feet.png")).unwrap();
    fails_naming(&plan_into(dir.path(), PLAN_B), &["feet.png"]);
    for (name, bytes) in snapshot(dir.path()) {
        assert!(
            old.get(&name) == Some(&bytes) || new.get(&name) == Some(&bytes),
            "{name}: neither the old file nor a complete new one ({} bytes)",
            bytes.len()
        );
    }
}

#[test]
fn a_plan_killed_at_any_moment_leaves_no_half_written_file() {
    let dir = tempfile::tempdir().unwrap();
    assert!(plan_into(dir.path(), PLAN_A).status.success());
    let old = snapshot(dir.path());
    let fresh = tempfile::tempdir().unwrap();
    let t0 = Instant::now();
    assert!(plan_into(fresh.path(), PLAN_B).status.success());
    let run = t0.elapsed();
    let new = snapshot(fresh.path());
    assert_ne!(old["joints.csv"], new["joints.csv"], "the two plans differ");
    // SIGKILL (no chance to clean up) at 12 moments spread over a whole run.
    for k in 1..=12u32 {
        let mut child = Command::new(env!("CARGO_BIN_EXE_dbot"))
            .args(["plan"])
            .args(PLAN_B)
            .args(["--out", dir.path().to_str().unwrap()])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(run * k / 12);
        let _ = child.kill();
        child.wait().unwrap();
        for (name, bytes) in snapshot(dir.path()) {
            if name.starts_with('.') {
                continue; // the command's own scratch files, never a result
            }
            assert!(
                old.get(&name) == Some(&bytes) || new.get(&name) == Some(&bytes),
                "killed at {k}/12 of {run:?}: {name} is neither the old file nor a complete new one \
                 ({} bytes)",
                bytes.len()
            );
        }
    }
}

#[test]
fn model_commands_on_missing_or_bad_files_name_them() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("gone.toml");
    fails_naming(
        &dbot(&["model", "show", "--model", missing.to_str().unwrap()]),
        &["gone.toml"],
    );
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "name = \"x\"\n[[body]]\nname = 3\n").unwrap();
    fails_naming(
        &dbot(&["model", "show", "--model", bad.to_str().unwrap()]),
        &["bad.toml"],
    );
    let nowhere = dir.path().join("no-dir").join("m.urdf");
    fails_naming(
        &dbot(&[
            "model",
            "export",
            "--model",
            "drosophibot2",
            "--urdf",
            nowhere.to_str().unwrap(),
        ]),
        &["m.urdf"],
    );
    fails_naming(
        &dbot(&["model", "export", "--model", "drosophibot2"]),
        &["--urdf"],
    );
}

#[test]
fn model_export_over_a_good_file_replaces_it_whole_or_not_at_all() {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("m.toml");
    let o = dbot(&[
        "model",
        "export",
        "--model",
        "drosophibot2",
        "--toml",
        target.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    let good = std::fs::read(&target).unwrap();
    // Export of another model over it, killed at moments spread over a run.
    let other = dir.path().join("other.toml");
    let t0 = Instant::now();
    let o = dbot(&[
        "model",
        "export",
        "--model",
        "scale-drosophila",
        "--toml",
        other.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    let run = t0.elapsed();
    let new = std::fs::read(&other).unwrap();
    for k in 1..=8u32 {
        let mut child = Command::new(env!("CARGO_BIN_EXE_dbot"))
            .args(["model", "export", "--model", "scale-drosophila", "--toml"])
            .arg(&target)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(run * k / 8);
        let _ = child.kill();
        child.wait().unwrap();
        let now = std::fs::read(&target).unwrap();
        assert!(
            now == good || now == new,
            "killed at {k}/8: {} bytes",
            now.len()
        );
    }
}

#[test]
fn dxl_on_a_missing_or_wrong_port_names_it() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("ttyNOPE");
    fails_naming(
        &dbot(&[
            "dxl",
            "--port",
            missing.to_str().unwrap(),
            "scan",
            "--max-id",
            "1",
        ]),
        &["ttyNOPE"],
    );
    // A regular file is not a serial port.
    let file = dir.path().join("not-a-tty");
    std::fs::write(&file, "").unwrap();
    fails_naming(
        &dbot(&[
            "dxl",
            "--port",
            file.to_str().unwrap(),
            "scan",
            "--max-id",
            "1",
        ]),
        &["not-a-tty"],
    );
    // /dev/null is not a serial port either; the command ends, it does not hang.
    let t0 = Instant::now();
    fails_naming(
        &dbot(&[
            "dxl",
            "--port",
            "/dev/null",
            "read",
            "--id",
            "1",
            "--field",
            "Model Number",
        ]),
        &["/dev/null"],
    );
    assert!(t0.elapsed() < Duration::from_secs(30));
}

#[test]
fn sim_bus_refuses_to_replace_a_file_and_names_bad_link_paths() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("precious");
    std::fs::write(&file, "data").unwrap();
    fails_naming(
        &dbot(&["sim-bus", "--link", file.to_str().unwrap(), "--quiet"]),
        &["precious"],
    );
    assert_eq!(std::fs::read(&file).unwrap(), b"data");
    let nowhere = dir.path().join("no-dir").join("bus");
    fails_naming(
        &dbot(&["sim-bus", "--link", nowhere.to_str().unwrap(), "--quiet"]),
        &["no-dir"],
    );
}

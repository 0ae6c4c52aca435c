//! Every plan directory a command writes (`dbot plan`, `dbot demo`'s `plan/`) is read by every
//! command that takes one (`table`, `compare`, `upload --plan` on the virtual robot), and the same
//! plan gives byte-identical step tables whichever way it is built: `table --plan`, `upload --plan`
//! (same gait name and CRC, read back from the board) and the demo's own table. An old or foreign
//! directory is refused by each reader naming plan.json and the format version.

use crate::cli_support;
use std::path::Path;
use std::process::Output;

use cli_support::in_dir;

fn dbot(dir: &Path, args: &[&str]) -> Output {
    let mut c = in_dir(dir);
    c.args(args);
    // No --allow-infeasible: `dbot plan`'s and the demo's defaults (servo-safe) are plans the
    // servos can follow, so every table here is built through the feasibility check.
    // Virtual stores are made here, not mistyped.
    if args.iter().any(|a| a.starts_with("virtual:")) {
        c.arg("--create");
    }
    c.output().unwrap()
}

fn ok(dir: &Path, args: &[&str]) -> String {
    let o = dbot(dir, args);
    assert!(
        o.status.success(),
        "dbot {args:?} failed:\n{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn fails(dir: &Path, args: &[&str]) -> String {
    let o = dbot(dir, args);
    assert!(!o.status.success(), "dbot {args:?} succeeded");
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `table --plan`'s bytes, and the name and CRC `upload --plan` reports after reading the stored
/// table back from the virtual robot (`upload` verifies the header and CRC it reads back).
fn tables_of(dir: &Path, plan: &str) -> (Vec<u8>, String) {
    let out = format!("{plan}.dbgt");
    ok(dir, &["table", "--plan", plan, "--out", &out]);
    let bytes = std::fs::read(dir.join(&out)).unwrap();
    let port = format!("virtual:{plan}.flash");
    let uploaded = ok(
        dir,
        &["upload", "--plan", plan, "--slot", "2", "--port", &port],
    );
    (bytes, uploaded)
}

#[test]
fn every_plan_directory_round_trips_through_every_reader_with_identical_tables() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // The same plan twice: `dbot plan`'s defaults are the demo's (table 1 of the paper at the
    // servo-safe swing, tripod, flat ground, the same dynamics options).
    ok(dir, &["plan", "--out", "walk"]);
    ok(dir, &["demo", "--steps", "1", "--out", "demo"]);

    for (plan, name) in [("walk", "walk"), ("demo/plan", "dbII tripod")] {
        let (bytes, uploaded) = tables_of(dir, plan);
        let t = protocol::GaitTable::parse(&bytes).unwrap();
        assert_eq!(t.header().name_str(), Some(name), "{plan}");
        // Drosophibot II drives 22 servos (paper section 2.4).
        assert_eq!(t.joint_count(), 22, "{plan}");
        let crc = format!("CRC {:#010x}", t.crc());
        assert!(
            uploaded.contains(&format!("slot 2: \"{name}\"")) && uploaded.contains(&crc),
            "{plan}: upload --plan stored another table than table --plan ({name}, {crc}):\n{uploaded}"
        );
        // Built twice from the same directory: the same bytes.
        let (again, _) = tables_of(dir, plan);
        assert_eq!(again, bytes, "{plan}");
    }
    // The demo's own step table is the one `table --plan` builds from the demo's plan directory,
    // and the one `dbot plan`'s directory of the same plan gives under the same name.
    let demo = std::fs::read(dir.join("demo/drosophibot2-tripod.dbgt")).unwrap();
    assert_eq!(demo, std::fs::read(dir.join("demo/plan.dbgt")).unwrap());
    ok(
        dir,
        &[
            "table",
            "--plan",
            "walk",
            "--name",
            "dbII tripod",
            "--out",
            "same.dbgt",
        ],
    );
    assert_eq!(demo, std::fs::read(dir.join("same.dbgt")).unwrap());

    // compare reads both kinds of directory: the same plan, so every common DoF's angles and
    // torques regress perfectly (R^2 = 1).
    let table = ok(dir, &["compare", "walk", "demo/plan", "--out", "cmp"]);
    let rows = std::fs::read_to_string(dir.join("cmp/compare.csv")).unwrap();
    let r2: Vec<f64> = rows
        .lines()
        .skip(1)
        .flat_map(|l| l.split(',').skip(3).filter_map(|v| v.parse().ok()))
        .collect();
    // 22 actuated DoF, each with an angle and a torque R^2.
    assert!(r2.len() >= 2 * 22, "{table}");
    assert!(r2.iter().all(|r| (r - 1.0).abs() < 1e-9), "{table}");
}

#[test]
fn old_or_foreign_plan_directories_are_refused_naming_the_file_and_version() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    ok(
        dir,
        &["plan", "--slices", "20", "--no-dynamics", "--out", "kin"],
    );
    // Without dynamics the directory reads, but a table needs the torques.
    let e = fails(dir, &["table", "--plan", "kin", "--out", "kin.dbgt"]);
    assert!(
        e.contains("joints.csv")
            && e.contains("torque_nm")
            && e.contains("by --no-dynamics or Plan.write(dynamics=False)?"),
        "{e}"
    );

    ok(dir, &["plan", "--slices", "20", "--out", "good"]);
    let json = std::fs::read_to_string(dir.join("good/plan.json")).unwrap();
    let mut value: serde_json::Value = serde_json::from_str(&json).unwrap();
    for (version, needle) in [
        (None, "no `format_version`"),
        (Some(7), "format_version 7, this dbot reads format 1"),
    ] {
        let old = dir.join("old");
        std::fs::create_dir_all(&old).unwrap();
        for f in ["joints.csv", "feet.csv", "model.toml"] {
            std::fs::copy(dir.join("good").join(f), old.join(f)).unwrap();
        }
        match version {
            None => value.as_object_mut().unwrap().remove("format_version"),
            Some(v) => value
                .as_object_mut()
                .unwrap()
                .insert("format_version".into(), v.into()),
        };
        std::fs::write(old.join("plan.json"), value.to_string()).unwrap();
        for args in [
            vec!["table", "--plan", "old", "--out", "old.dbgt"],
            vec!["compare", "good", "old", "--out", "cmp"],
            vec!["upload", "--plan", "old", "--port", "virtual"],
        ] {
            let e = fails(dir, &args);
            assert!(
                e.contains("old/plan.json") && e.contains(needle),
                "{args:?}: {e}"
            );
        }
    }

    // A damaged row is named with its file and line.
    let joints = std::fs::read_to_string(dir.join("good/joints.csv")).unwrap();
    let mut lines: Vec<String> = joints.lines().map(String::from).collect();
    lines[3] = lines[3].replacen("0,", "x,", 1);
    std::fs::write(dir.join("good/joints.csv"), lines.join("\n") + "\n").unwrap();
    let e = fails(dir, &["table", "--plan", "good", "--out", "g.dbgt"]);
    assert!(
        e.contains("good/joints.csv line 4") && e.contains("slice `x`"),
        "{e}"
    );
}

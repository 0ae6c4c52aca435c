//! `dbot compare` takes trials (issue 29 item 1) as it takes plans: a trial walked on the virtual
//! robot against the plan it walked, a trial against itself, and a trial too short to compare.
//!
//! Independent truth: the R^2 of the front-left FTi recomputed here from the files themselves (the
//! trial's telemetry.csv averaged per slice over steps 1 and 2 by hand, the plan's joints.csv), as
//! the squared Pearson correlation of the paper's tables; a series against itself has R^2 = 1.

use crate::board_fakes;
use std::collections::BTreeMap;
use std::path::Path;

use board::trial::latest_trial;
use board_fakes::cli::{fails_naming, run, strings};

fn ok(dir: &Path, args: &[&str]) -> String {
    let d = run(dir, &strings(args));
    assert!(d.status.success(), "{args:?}: {}{}", d.stdout, d.stderr);
    d.stdout
}

/// compare.csv's rows: (leg, dof) -> (r2_angle, r2_torque) as written.
fn compare_csv(out: &Path) -> BTreeMap<(String, String), (String, String)> {
    let mut rd = csv::Reader::from_path(out.join("compare.csv")).unwrap();
    rd.records()
        .map(|r| {
            let r = r.unwrap();
            ((r[0].into(), r[1].into()), (r[3].into(), r[4].into()))
        })
        .collect()
}

fn pearson_r2(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        sab += (x - ma) * (y - mb);
        saa += (x - ma) * (x - ma);
        sbb += (y - mb) * (y - mb);
    }
    sab * sab / (saa * sbb)
}

#[test]
fn a_trial_compares_with_its_plan_and_with_itself() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(d, &["plan", "--slices", "40", "--out", "p"]);
    ok(d, &["table", "--plan", "p", "--out", "p/g.dbgt"]);
    let record = |steps: &str| {
        ok(
            d,
            &[
                "record", "--out", "trials", "--table", "p/g.dbgt", "--plan", "p", "--play", "0",
                "--steps", steps, "--port", "virtual",
            ],
        );
        latest_trial(&d.join("trials")).unwrap().unwrap()
    };
    let trial = record("3");
    let t = trial.to_str().unwrap();

    // Against itself: every DoF's angle R^2 is 1.
    ok(d, &["compare", t, t, "--out", "self"]);
    let rows = compare_csv(&d.join("self"));
    assert!(rows.len() >= 18, "{rows:?}");
    for (k, (a, _)) in &rows {
        assert_eq!(a, "1.000", "{k:?}");
    }

    // Against its plan: the servos follow the table, so every angle R^2 is high; LF FTi's is the
    // one computed here by hand from the two files.
    let out = ok(d, &["compare", "p", t, "--out", "vs-plan"]);
    let rows = compare_csv(&d.join("vs-plan"));
    for (k, (a, _)) in &rows {
        let a: f64 = a.parse().unwrap_or_else(|_| panic!("{k:?}: `{a}`"));
        assert!(a > 0.9, "{k:?}: R^2 {a}\n{out}");
    }
    let planned: Vec<f64> = csv::Reader::from_path(d.join("p/joints.csv"))
        .unwrap()
        .records()
        .map(Result::unwrap)
        .filter(|r| &r[2] == "LF" && &r[3] == "FTi")
        .map(|r| r[4].parse().unwrap())
        .collect();
    assert_eq!(planned.len(), 40);
    let mut rd = csv::Reader::from_path(trial.join("telemetry.csv")).unwrap();
    let h = rd.headers().unwrap().clone();
    let col = |name: &str| h.iter().position(|c| c == name).unwrap();
    let (step, slice, joint, present, flags) = (
        col("step"),
        col("slice"),
        col("joint"),
        col("present_rad"),
        col("flags"),
    );
    let mut sums = vec![(0.0, 0.0); 40];
    for r in rd.records().map(Result::unwrap) {
        let s: u32 = r[step].parse().unwrap();
        if &r[joint] != "LF_FTi" || !(1..3).contains(&s) || r[flags].parse::<u8>().unwrap() & 9 != 0
        {
            continue;
        }
        let e = &mut sums[r[slice].parse::<usize>().unwrap()];
        e.0 += r[present].parse::<f64>().unwrap();
        e.1 += 1.0;
    }
    let measured: Vec<f64> = sums.iter().map(|(s, n)| s / n).collect();
    // The library's trace is that average, slice by slice (to the CSV's 1e-9 rad and summing order).
    let traces = lab::trial_traces::trial_traces(&trial).unwrap();
    let fti = traces
        .iter()
        .find(|t| t.leg == planner::model::Leg::LF && t.kind == planner::model::JointKind::FTi)
        .unwrap();
    assert_eq!(fti.angle.len(), 40);
    for (s, (a, b)) in fti.angle.iter().zip(&measured).enumerate() {
        assert!((a - b).abs() < 1e-9, "slice {s}: {a} vs {b}");
    }
    let by_hand = pearson_r2(&planned, &measured);
    let written: f64 = rows[&("LF".into(), "FTi".into())].0.parse().unwrap();
    assert!(
        (written - by_hand).abs() <= 0.0005,
        "{written} vs {by_hand:.4}"
    );

    // One step is too few: step 0 holds the start ramp.
    let short = record("1");
    let r = run(
        d,
        &strings(&["compare", "p", short.to_str().unwrap(), "--out", "short"]),
    );
    fails_naming(&r, "compare a 1-step trial", &["at least 2", "start ramp"]);
}

//! The plan CSVs read well (issue 20 item 7): plain decimals (no `4.65e-1`), a README.md beside
//! them that states each file's conventions, and the angles still the planner's to 1e-9 rad.
//! `dbot plan` writes strain.csv (tidy, plain decimals, one row per slice and gauge in the
//! model's gauge order, the board's for Drosophibot II) and strain.png; the readings are the
//! planner's prediction for the same plan, to the digits kept.

use planner::dynamics::{DynamicsOptions, plan_inputs, solve_cycle};
use planner::gait::StepParams;
use planner::model::builtin;
use planner::strain::csv::HEADER;
use planner::strain::predict;

/// `dbot plan --slices 20` (its defaults otherwise: the servo-safe preset of the built-in robot)
/// into a fresh folder.
fn planned() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_dbot"))
        .args([
            "plan",
            "--slices",
            "20",
            "--out",
            dir.path().to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    dir
}

#[test]
fn plan_csvs_are_plain_decimals_with_a_readme() {
    let dir = planned();
    for f in ["joints.csv", "feet.csv", "joint_forces.csv"] {
        let mut rd = csv::Reader::from_path(dir.path().join(f)).unwrap();
        let headers = rd.headers().unwrap().clone();
        for rec in rd.records() {
            let rec = rec.unwrap();
            for (h, v) in headers.iter().zip(rec.iter()) {
                if h == "leg" || h == "joint" {
                    continue;
                }
                assert!(
                    !v.contains(['e', 'E']),
                    "{f} {h}: `{v}` is not a plain decimal"
                );
                assert!(v.parse::<f64>().is_ok(), "{f} {h}: `{v}`");
            }
        }
    }
    let readme = std::fs::read_to_string(dir.path().join("README.md")).unwrap();
    assert!(readme.contains("the parent body exerts on the child body"));
    assert!(readme.contains("about the joint origin"));

    // Angles as the planner computes them (slice 7, every joint), to the digits kept.
    let m = builtin("drosophibot2").unwrap();
    let mut p = StepParams::table1(&m.name);
    p.slices = 20;
    let plan = planner::plan::plan(&m, &p).unwrap();
    let mut rd = csv::Reader::from_path(dir.path().join("joints.csv")).unwrap();
    let angles: Vec<f64> = rd
        .records()
        .map(|r| r.unwrap())
        .filter(|r| &r[0] == "7")
        .map(|r| r[4].parse().unwrap())
        .collect();
    assert_eq!(angles.len(), m.joints.len());
    for (a, q) in angles.iter().zip(&plan.q[7]) {
        assert!((a - q).abs() < 1e-9, "{a} vs {q}");
    }
}

#[test]
fn plan_writes_a_tidy_strain_csv_and_plot() {
    let dir = planned();
    assert!(dir.path().join("strain.png").is_file());
    let mut rd = csv::Reader::from_path(dir.path().join("strain.csv")).unwrap();
    assert_eq!(rd.headers().unwrap().iter().collect::<Vec<_>>(), HEADER);
    let rows: Vec<csv::StringRecord> = rd.records().map(Result::unwrap).collect();

    // `dbot plan`'s defaults: the servo-safe preset of the built-in robot.
    let m = builtin("drosophibot2").unwrap();
    let mut p = StepParams::preset(planner::gait::DEFAULT_PRESET, &m.name).unwrap();
    p.slices = 20;
    let plan = planner::plan::plan(&m, &p).unwrap();
    let inputs = plan_inputs(&plan);
    let cycle = solve_cycle(&plan.model, &inputs, &DynamicsOptions::default()).unwrap();
    let strain = predict(&plan.model, &inputs, &cycle).unwrap();
    assert_eq!(rows.len(), 20 * 36);
    for (i, r) in rows.iter().enumerate() {
        let (s, g) = (i / 36, i % 36);
        assert_eq!(&r[0], s.to_string());
        assert_eq!(&r[2], plan.model.gauges[g].name);
        assert_eq!(&r[3], plan.model.gauges[g].leg.name());
        for v in r.iter().skip(5) {
            assert!(
                !v.contains(['e', 'E']),
                "row {i}: `{v}` is not a plain decimal"
            );
        }
        let got: f64 = r[5].parse().unwrap();
        let want = strain.readings[s][g].microstrain;
        assert!(
            (got - want).abs() <= 1e-8 * want.abs().max(1.0),
            "row {i}: {got} vs {want}"
        );
    }
    assert_eq!(&rows[0][2], "LH_troch_axial");
    assert_eq!(&rows[35][2], "RF_femur_axial");
}

//! `dbot plan` writes strain.csv (tidy, plain decimals, one row per slice and gauge in the
//! model's gauge order, the board's for Drosophibot II) and strain.png; the readings are the
//! planner's prediction for the same plan, to the digits kept.

use planner::dynamics::{DynamicsOptions, plan_inputs, solve_cycle};
use planner::gait::StepParams;
use planner::model::builtin;
use planner::strain::csv::HEADER;
use planner::strain::predict;

#[test]
fn plan_writes_a_tidy_strain_csv_and_plot() {
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

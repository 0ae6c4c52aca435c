//! The plan CSVs read well (issue 20 item 7): plain decimals (no `4.65e-1`), a README.md beside
//! them that states each file's conventions, and the angles still the planner's to 1e-9 rad.

use planner::gait::StepParams;
use planner::model::builtin;

#[test]
fn plan_csvs_are_plain_decimals_with_a_readme() {
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

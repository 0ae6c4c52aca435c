//! `dbot record` without `--table` names joints by the servo IDs the board reports for the played
//! slot (GetJointMap), not by assuming the model's order: a table whose joints run in reverse order
//! gives the same joint names per joint as `record --table` with that table.

use firmware::testkit::SyntheticGait;

/// The joint names of the CSV's first bus cycle, in the board's joint order.
fn first_cycle_joints(csv: &std::path::Path) -> Vec<String> {
    let mut rd = csv::Reader::from_path(csv).unwrap();
    let h = rd.headers().unwrap().clone();
    let col = |name: &str| h.iter().position(|x| x == name).unwrap();
    let (cycle, joint) = (col("cycle"), col("joint"));
    let rows: Vec<csv::StringRecord> = rd.records().map(|r| r.unwrap()).collect();
    let first = rows[0][cycle].to_string();
    rows.iter()
        .take_while(|r| r[cycle] == first)
        .map(|r| r[joint].to_string())
        .collect()
}

#[test]
fn record_without_table_names_joints_by_the_boards_servo_ids() {
    let dir = tempfile::tempdir().unwrap();
    let t = dir.path().join("rev.dbgt");
    let mut g = SyntheticGait::new(40, 0.5);
    g.joints.reverse();
    std::fs::write(&t, g.build()).unwrap();
    let image = format!("virtual:{}", dir.path().join("r.flash").display());
    let run = |args: &[&str]| {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_dbot"))
            .args(args)
            .args(["--port", &image, "--create"])
            .current_dir(dir.path())
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{args:?}: {}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        );
    };
    run(&["upload", "--table", t.to_str().unwrap()]);
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    let rec = |out: &std::path::Path| {
        vec![
            "record".to_owned(),
            "--out".to_owned(),
            out.display().to_string(),
            "--play".to_owned(),
            "0".to_owned(),
            "--steps".to_owned(),
            "1".to_owned(),
        ]
    };
    let mut with_table = rec(&a);
    with_table.extend(["--table".to_owned(), t.display().to_string()]);
    run(&with_table.iter().map(String::as_str).collect::<Vec<_>>());
    run(&rec(&b).iter().map(String::as_str).collect::<Vec<_>>());
    // Each recording is the one trial folder in its --out.
    let trial = |d: &std::path::Path| board::trial::latest_trial(d).unwrap().unwrap();
    let by_table = first_cycle_joints(&trial(&a).join("telemetry.csv"));
    let by_board = first_cycle_joints(&trial(&b).join("telemetry.csv"));
    assert_eq!(by_table.len(), 22);
    // Joint 0 of the reversed table is servo 22, the model's last servo joint, not LF_ThC1.
    assert_ne!(by_table[0], "LF_ThC1");
    assert!(by_table.iter().all(|n| !n.starts_with('J')), "{by_table:?}");
    assert_eq!(by_board, by_table);
}

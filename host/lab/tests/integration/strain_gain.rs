//! The strain comparison fits a gauge's gain, counts per predicted microstrain, against a known
//! one (issue 43 item 5): a trial recorded on the virtual robot is given gauges whose counts are
//! exactly baseline + gain x the plan's prediction at the slice each sample's record played, and
//! `lab::strain_compare::compare_trial` (behind `dbot compare --strain` and Python's
//! `dbot.compare_strain`) must give back those gains, R^2 1 and no residual. Before, the compare
//! tests held Python against the CLI on the same library and never asserted a gain.

use std::fmt::Write as _;

use lab::trial_record::{TrialHooks, TrialRequest, record_trial};

struct Quiet;

impl TrialHooks for Quiet {
    fn should_stop(&mut self) -> bool {
        false
    }
    fn say(&mut self, _: &str) {}
}

/// The prediction of the two gauges at `slice`, microstrain (one positive, one negative).
fn predicted(gauge: usize, slice: usize) -> f64 {
    match gauge {
        0 => 10.0 + slice as f64,
        _ => -(5.0 + 2.0 * slice as f64),
    }
}

#[test]
fn a_known_gain_is_fitted_back() {
    let model = planner::model::builtin("drosophibot2").unwrap();
    let params = planner::gait::StepParams::preset("servo-safe", &model.name).unwrap();
    let plan = planner::plan::plan(&model, &params).unwrap();
    let bytes = planner::plan::table::step_table(&plan, None, "safe").unwrap();
    let slices = protocol::GaitTable::parse(&bytes).unwrap().slice_count();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("trials");
    let mut board = physics::open("virtual").unwrap();
    gate::upload(&mut board, 0, &bytes).unwrap();
    let req = TrialRequest {
        trial: Some("known gain".to_owned()),
        command_line: vec!["test".to_owned()],
        ..TrialRequest::playing(&out, 0, Some(1), model.clone())
    };
    let trial = record_trial(&mut board, &req, &mut Quiet).unwrap().path;
    let rows = board::trial::read_trial(&trial).unwrap().rows;

    // The plan's prediction of two gauges per slice.
    let names = board::strain::channels::names();
    let plan_dir = dir.path().join("plan");
    std::fs::create_dir_all(&plan_dir).unwrap();
    let mut text = String::from("slice,gauge,microstrain\n");
    for s in 0..slices {
        for (g, name) in names.iter().enumerate().take(2) {
            writeln!(text, "{s},{name},{}", predicted(g, s)).unwrap();
        }
    }
    std::fs::write(plan_dir.join(planner::strain::csv::STRAIN_CSV), text).unwrap();

    // Zero-strain counts, and one sample at every walking record's time: baseline + gain x the
    // prediction at that record's slice (other gauges at their baseline).
    let gains = [3.5, -1.25];
    let baseline: Vec<f64> = (0..names.len()).map(|c| 1000.0 + c as f64).collect();
    let cells = |v: &[f64]| v.iter().map(f64::to_string).collect::<Vec<_>>().join(",");
    std::fs::write(
        trial.join(board::strain::recorder::BASELINE_CSV),
        format!("{}\n{}\n", names.join(","), cells(&baseline)),
    )
    .unwrap();
    let mut strain = format!("time_s,{}\n", names.join(","));
    let mut samples = 0;
    for r in rows.iter().filter(|r| r.joint == 0 && r.step < 1) {
        let mut counts = baseline.clone();
        for (g, gain) in gains.iter().enumerate() {
            counts[g] += gain * predicted(g, usize::from(r.slice));
        }
        writeln!(strain, "{},{}", r.time_s, cells(&counts)).unwrap();
        samples += 1;
    }
    std::fs::write(trial.join(board::strain::recorder::STRAIN_CSV), strain).unwrap();
    assert!(samples > 100, "{samples} walking records");

    let fits = lab::strain_compare::compare_trial(&trial, &plan_dir).unwrap();
    assert_eq!(fits.len(), 2, "{fits:?}");
    for (f, (name, gain)) in fits.iter().zip(names.iter().zip(gains)) {
        assert_eq!(&f.gauge, name);
        assert_eq!(f.samples, samples);
        let fitted = f.gain.unwrap();
        assert!(
            (fitted - gain).abs() < 1e-9,
            "{name}: gain {fitted}, made {gain}"
        );
        assert!((f.r2.unwrap() - 1.0).abs() < 1e-9, "{f:?}");
        assert!(f.rms_residual_counts.unwrap() < 1e-9, "{f:?}");
    }
}

use crate::gate;

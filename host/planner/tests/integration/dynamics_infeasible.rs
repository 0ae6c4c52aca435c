//! An infeasible constrained plan is an error that names the slices, the feet and what would make
//! it feasible. The case: Drosophibot II on a 15 degree incline (table 1 otherwise), where the
//! unconstrained optimum needs the front feet to pull at slices 10-14 and 60-65 (the body's weight
//! falls outside the push-only support); at 12 cm body height the same walk is feasible.

use planner::dynamics::{DynamicsError, DynamicsOptions, plan_inputs, solve_cycle};
use planner::gait::{PerPair, StepParams};
use planner::model::builtin;

fn incline(body_height: f64) -> Result<planner::dynamics::CycleSolution, DynamicsError> {
    let model = builtin("drosophibot2").unwrap();
    let mut p = StepParams::table1(&model.name);
    p.terrain = planner::terrain::Ground::parse("incline:15").unwrap();
    p.body_height_m = PerPair::all(body_height);
    let plan = planner::plan::plan(&model, &p).unwrap();
    let opts = DynamicsOptions {
        push_only: true,
        ..Default::default()
    };
    solve_cycle(&model, &plan_inputs(&plan), &opts)
}

#[test]
fn incline_15_names_slices_feet_and_remedy() {
    let e = incline(0.175).unwrap_err();
    let text = e.to_string();
    match e {
        DynamicsError::Infeasible {
            slices,
            constraints,
            need,
            advice,
        } => {
            assert_eq!(slices, "10-14, 60-65");
            assert_eq!(constraints, "push-only feet");
            assert!(
                need.contains("LF pulls") && need.contains("RF pulls"),
                "{need}"
            );
            assert!(advice.contains("lower body height") && advice.contains("smaller incline"));
        }
        other => panic!("expected Infeasible, got {other:?}"),
    }
    assert!(
        !text.contains("Infeasible") && !text.contains("AlmostSolved"),
        "{text}"
    );
    // The remedy it names works: 12 cm instead of 17.5 cm body height.
    let lower = incline(0.12).unwrap();
    // Push-only holds (slips listed here only leave the mu = 0.5 cone; none pulls).
    assert!(
        lower.report.slips.iter().all(|s| s.normal > -1e-6),
        "{:?}",
        lower.report.slips
    );
}

//! The section wrench two ways on walking plans of both built-in models, every slice and gauge:
//! from the distal free body (what `strain::predict` reports) and rebuilt from the proximal side,
//! the solver's joint force and moment at the segment's proximal joint minus the proximal part's
//! own inertial and gravity loads. They must agree to rounding (1e-9 of the leg's load scale).

use planner::dynamics::{DynamicsOptions, plan_inputs, solve_cycle};
use planner::gait::StepParams;
use planner::model::builtin;
use planner::plan::plan;
use planner::strain::cut::{Site, SliceBodies, distal_wrench, in_section_frame, proximal_wrench};
use planner::strain::predict;

fn check(model_name: &str) {
    let model = builtin(model_name).unwrap();
    let mut params = StepParams::table1(model_name);
    params.slices = 40;
    let plan = plan(&model, &params).unwrap();
    let model = &plan.model;
    let inputs = plan_inputs(&plan);
    let cycle = solve_cycle(model, &inputs, &DynamicsOptions::default()).unwrap();
    let strain = predict(model, &inputs, &cycle).unwrap();
    assert_eq!(model.gauges.len(), 36);
    // Load scale: the total weight (N) and weight times leg length (N m).
    let weight: f64 = model.bodies.iter().map(|b| b.mass).sum::<f64>() * 9.81;
    let reach = model.leg_length(model.legs()[0]);
    let sites: Vec<Site> = model
        .gauges
        .iter()
        .map(|g| Site::of(model, g).unwrap())
        .collect();
    let mut peak: f64 = 0.0;
    for (s, (input, sol)) in inputs.iter().zip(&cycle.slices).enumerate() {
        let bodies = SliceBodies::of(model, input);
        for (gi, (g, site)) in model.gauges.iter().zip(&sites).enumerate() {
            let frame = site.frame(g, &bodies.motions[site.segment]);
            let main = distal_wrench(model, site, &frame, &bodies, &sol.grf);
            let other = proximal_wrench(
                model,
                site,
                &frame,
                &bodies,
                &sol.joint_force,
                &sol.joint_moment,
            );
            let df = (main.0 - other.0).norm();
            let dm = (main.1 - other.1).norm();
            assert!(
                df <= 1e-9 * weight && dm <= 1e-9 * weight * reach,
                "{model_name} slice {s} {}: force differs by {df:e} N, moment by {dm:e} N m",
                g.name
            );
            // predict reports the main path, in the section frame.
            let reported = strain.readings[s][gi].wrench;
            let w = in_section_frame(&frame, &main);
            assert!((reported.force - w.force).norm() <= 1e-12 * weight);
            assert!((reported.moment - w.moment).norm() <= 1e-12 * weight * reach);
            peak = peak.max(main.1.norm() / (weight * reach));
        }
    }
    // Not vacuous: the gauges carry moments of the order of the weight times the leg length.
    assert!(
        peak > 0.01,
        "{model_name}: peak section moment only {peak} W L"
    );
}

#[test]
fn drosophibot2_walking_section_wrench_agrees_from_both_sides() {
    check("drosophibot2");
}

#[test]
fn scale_drosophila_walking_section_wrench_agrees_from_both_sides() {
    check("scale-drosophila");
}

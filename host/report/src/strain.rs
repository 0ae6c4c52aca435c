//! Predicted gauge strain of one plan, and a walk's simulated gauges beside it: one panel per
//! leg with that leg's gauges (microstrain), stance shaded.

use std::path::Path;

use crate::legs::{Panel, PlotError, Trace, plot_leg_panels, stance_spans};
use planner::plan::Plan;
use planner::strain::StrainPrediction;

/// strain.png: every gauge of each leg in microstrain over the cycle.
pub fn plot_strain(plan: &Plan, strain: &StrainPrediction, path: &Path) -> Result<(), PlotError> {
    let model = &plan.model;
    let times: Vec<f64> = (0..plan.slices()).map(|s| plan.time(s)).collect();
    let panels = plan
        .legs
        .iter()
        .enumerate()
        .filter(|(_, leg)| model.gauges.iter().any(|g| g.leg == **leg))
        .map(|(li, leg)| {
            let st: Vec<bool> = (0..plan.slices()).map(|s| plan.stance[s][li]).collect();
            Panel {
                leg: *leg,
                title: format!("{} predicted strain", leg.name()),
                traces: model
                    .gauges
                    .iter()
                    .enumerate()
                    .filter(|(_, g)| g.leg == *leg)
                    .enumerate()
                    .map(|(k, (gi, g))| Trace {
                        label: g
                            .name
                            .strip_prefix(&format!("{}_", leg.name()))
                            .unwrap_or(&g.name)
                            .to_string(),
                        values: strain.readings.iter().map(|s| s[gi].microstrain).collect(),
                        dashed: k >= 3,
                        colour: k,
                    })
                    .collect(),
                stance: stance_spans(&st, plan.dt),
            }
        })
        .collect::<Vec<_>>();
    plot_leg_panels(path, &panels, &times, "time (s)", "strain (microstrain)")
}

/// strain_vs_plan.png of a walk: per leg its gauges over the step phase, predicted (solid) and the
/// simulated mean per slice over the walked steps (dashed, same colour). `predicted[gauge][slice]`
/// and `simulated[gauge][slice]` in the model's gauge order, microstrain; a slice no sample fell
/// in is drawn at the slice before it (the board's latest sample), or the first one sampled.
pub fn plot_strain_walk(
    plan: &Plan,
    predicted: &[Vec<f64>],
    simulated: &[Vec<Option<f64>>],
    path: &Path,
) -> Result<(), PlotError> {
    let model = &plan.model;
    let times: Vec<f64> = (0..plan.slices()).map(|s| plan.time(s)).collect();
    let held = |v: &[Option<f64>]| -> Vec<f64> {
        let first = v.iter().flatten().next().copied().unwrap_or(0.0);
        let mut last = first;
        v.iter()
            .map(|x| {
                if let Some(x) = x {
                    last = *x;
                }
                last
            })
            .collect()
    };
    let panels = plan
        .legs
        .iter()
        .enumerate()
        .filter(|(_, leg)| model.gauges.iter().any(|g| g.leg == **leg))
        .map(|(li, leg)| {
            let st: Vec<bool> = (0..plan.slices()).map(|s| plan.stance[s][li]).collect();
            let mut traces = Vec::new();
            for (k, (gi, g)) in model
                .gauges
                .iter()
                .enumerate()
                .filter(|(_, g)| g.leg == *leg)
                .enumerate()
            {
                let label = g
                    .name
                    .strip_prefix(&format!("{}_", leg.name()))
                    .unwrap_or(&g.name)
                    .to_string();
                traces.push(Trace {
                    label: label.clone(),
                    values: predicted.get(gi).cloned().unwrap_or_default(),
                    dashed: false,
                    colour: k,
                });
                traces.push(Trace {
                    label: "simulated".to_string(),
                    values: simulated.get(gi).map(|v| held(v)).unwrap_or_default(),
                    dashed: true,
                    colour: k,
                });
            }
            Panel {
                leg: *leg,
                title: format!(
                    "{}: predicted (solid) vs simulated (dashed, mean over steps)",
                    leg.name()
                ),
                traces,
                stance: stance_spans(&st, plan.dt),
            }
        })
        .collect::<Vec<_>>();
    plot_leg_panels(
        path,
        &panels,
        &times,
        "time in the step (s)",
        "strain (microstrain)",
    )
}

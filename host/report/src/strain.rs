//! Predicted gauge strain of one plan, and a walk's simulated gauges beside it: one panel per
//! leg with that leg's gauges (microstrain), stance shaded.

use std::path::Path;

use crate::legs::{Panel, PlotError, Trace, plot_leg_panels, stance_spans};
use planner::model::Leg;
use planner::plan::Plan;
use planner::strain::StrainPrediction;

/// strain.png: every gauge of each leg in microstrain over the cycle.
pub fn plot_strain(plan: &Plan, strain: &StrainPrediction, path: &Path) -> Result<(), PlotError> {
    let times: Vec<f64> = (0..plan.slices()).map(|s| plan.time(s)).collect();
    let panels = gauge_panels(
        plan,
        |leg| format!("{} predicted strain", leg.name()),
        |k, gi, label| {
            vec![Trace {
                label,
                values: strain.readings.iter().map(|s| s[gi].microstrain).collect(),
                dashed: k >= 3,
                colour: k,
            }]
        },
    );
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
    let panels = gauge_panels(
        plan,
        |leg| {
            format!(
                "{}: predicted (solid) vs simulated (dashed, mean over steps)",
                leg.name()
            )
        },
        |k, gi, label| {
            vec![
                Trace {
                    label,
                    values: predicted.get(gi).cloned().unwrap_or_default(),
                    dashed: false,
                    colour: k,
                },
                Trace {
                    label: "simulated".to_string(),
                    values: simulated.get(gi).map(|v| held(v)).unwrap_or_default(),
                    dashed: true,
                    colour: k,
                },
            ]
        },
    );
    plot_leg_panels(
        path,
        &panels,
        &times,
        "time in the step (s)",
        "strain (microstrain)",
    )
}

/// One panel per leg of `plan` that carries gauges, stance shaded, titled by `title`; the k-th
/// gauge of the leg (index `gi` in the model's gauges, `label` its name without the leg's
/// prefix) is drawn as the traces `traces(k, gi, label)` gives.
fn gauge_panels(
    plan: &Plan,
    title: impl Fn(Leg) -> String,
    traces: impl Fn(usize, usize, String) -> Vec<Trace>,
) -> Vec<Panel> {
    let model = &plan.model;
    plan.legs
        .iter()
        .enumerate()
        .filter(|(_, leg)| model.gauges.iter().any(|g| g.leg == **leg))
        .map(|(li, &leg)| {
            let st: Vec<bool> = (0..plan.slices()).map(|s| plan.stance[s][li]).collect();
            let prefix = format!("{}_", leg.name());
            Panel {
                leg,
                title: title(leg),
                traces: model
                    .gauges
                    .iter()
                    .enumerate()
                    .filter(|(_, g)| g.leg == leg)
                    .enumerate()
                    .flat_map(|(k, (gi, g))| {
                        let label = g.name.strip_prefix(&prefix).unwrap_or(&g.name);
                        traces(k, gi, label.to_string())
                    })
                    .collect(),
                stance: stance_spans(&st, plan.dt),
            }
        })
        .collect()
}

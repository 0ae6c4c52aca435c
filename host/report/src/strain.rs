//! Predicted gauge strain of one plan: one panel per leg with that leg's gauges (microstrain),
//! stance shaded.

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

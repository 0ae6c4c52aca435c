//! Dynamics plots of one plan: actuated torque per DoF per leg (paper figure 4) and GRF
//! components and magnitude per leg (figure S9), stance shaded.

use std::path::Path;

use crate::legs::{
    Panel, PlotError, Trace, force_unit, plot_leg_panels, stance_spans, torque_unit,
};
use planner::dynamics::CycleSolution;
use planner::plan::Plan;

fn times(plan: &Plan) -> Vec<f64> {
    (0..plan.slices()).map(|s| plan.time(s)).collect()
}

fn leg_stance(plan: &Plan, li: usize) -> Vec<(f64, f64)> {
    let st: Vec<bool> = (0..plan.slices()).map(|s| plan.stance[s][li]).collect();
    stance_spans(&st, plan.dt)
}

/// Actuated torque of every DoF, one panel per leg.
pub fn plot_torques(plan: &Plan, cycle: &CycleSolution, path: &Path) -> Result<(), PlotError> {
    let model = &plan.model;
    let peak = cycle
        .slices
        .iter()
        .flat_map(|s| s.torque.iter())
        .fold(0.0f64, |m, t| m.max(t.abs()));
    let (unit, scale) = torque_unit(peak);
    let panels = plan
        .legs
        .iter()
        .enumerate()
        .map(|(li, leg)| Panel {
            leg: *leg,
            title: format!("{} actuated torque", leg.name()),
            traces: model
                .leg_chain(*leg)
                .into_iter()
                .filter(|&j| model.is_actuated(j))
                .enumerate()
                .map(|(k, j)| Trace {
                    label: model.joints[j].kind.name().to_string(),
                    values: cycle.slices.iter().map(|s| s.torque[j] * scale).collect(),
                    dashed: false,
                    colour: k,
                })
                .collect(),
            stance: leg_stance(plan, li),
        })
        .collect::<Vec<_>>();
    plot_leg_panels(
        path,
        &panels,
        &times(plan),
        "time (s)",
        &format!("torque ({unit})"),
    )
}

/// GRF x, y, z and magnitude, one panel per leg.
pub fn plot_grf(plan: &Plan, cycle: &CycleSolution, path: &Path) -> Result<(), PlotError> {
    let model = &plan.model;
    let peak = cycle
        .slices
        .iter()
        .flat_map(|s| s.grf.iter())
        .fold(0.0f64, |m, g| m.max(g.norm()));
    let (unit, scale) = force_unit(peak);
    let mut panels = Vec::new();
    for (li, leg) in plan.legs.iter().enumerate() {
        let Some(f) = model.feet.iter().position(|f| f.leg == *leg) else {
            continue;
        };
        let comp = |name: &str, k: usize, get: &dyn Fn(&nalgebra::Vector3<f64>) -> f64| Trace {
            label: name.into(),
            values: cycle
                .slices
                .iter()
                .map(|s| get(&s.grf[f]) * scale)
                .collect(),
            dashed: false,
            colour: k,
        };
        panels.push(Panel {
            leg: *leg,
            title: format!("{} ground reaction force", leg.name()),
            traces: vec![
                comp("x", 0, &|g| g.x),
                comp("y", 1, &|g| g.y),
                comp("z", 2, &|g| g.z),
                comp("|F|", 7, &|g| g.norm()),
            ],
            stance: leg_stance(plan, li),
        });
    }
    plot_leg_panels(
        path,
        &panels,
        &times(plan),
        "time (s)",
        &format!("force ({unit})"),
    )
}

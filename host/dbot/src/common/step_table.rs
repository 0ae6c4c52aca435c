//! The step table of a solved plan, as `demo` and `upload --plan` build it.

use anyhow::Context;
use planner::dynamics::table::{gait_table, joint_specs, stance_bits};
use planner::plan::Plan;

use crate::args::dynamics::PlanDynamics;

/// The step table of a solved plan (the dynamics module's builder): every joint with a servo, its
/// planned angle and modelled torque per slice, stance bits per leg; and the servos' joint names.
pub fn step_table(plan: &Plan, d: &PlanDynamics) -> anyhow::Result<(Vec<u8>, Vec<String>)> {
    let (index, _) = joint_specs(&plan.model)?;
    let names = index
        .iter()
        .map(|&j| plan.model.joints[j].name.clone())
        .collect();
    let torques = planner::dynamics::output::torque_rows(&d.cycle);
    let stance: Vec<u8> = plan
        .stance
        .iter()
        .map(|s| stance_bits(&plan.legs, s))
        .collect();
    let table = gait_table(
        &plan.model,
        "dbII tripod",
        plan.period_s,
        plan.params.duty,
        &plan.q,
        &torques,
        &stance,
    )
    .context("building the step table")?;
    Ok((table, names))
}

//! Whether the servos can follow a plan, as a rule: refused unless overridden, and with the
//! override a warning naming the same joints, slices and margins.

use planner::plan::feasibility::Feasibility;

use super::{Overridden, Overrides, RuleError, Violations};

/// Refuses the plan or table `what` when `f` lists anything a servo cannot do, unless
/// `overrides.allow_infeasible`; then returns the warning to show.
pub fn enforce(
    f: &Feasibility,
    what: &str,
    overrides: Overrides,
) -> Result<Option<Overridden>, RuleError> {
    if f.is_feasible() {
        return Ok(None);
    }
    let violations = Violations(f.violations.clone());
    if overrides.allow_infeasible {
        Ok(Some(Overridden::Infeasible {
            what: what.to_owned(),
            violations,
        }))
    } else {
        Err(RuleError::Infeasible {
            what: what.to_owned(),
            violations,
        })
    }
}

/// The feasibility of a plan directory's planned angles and torques.
pub fn of_plan_dir(plan: &planner::plan_dir::PlanDir) -> Feasibility {
    planner::plan::feasibility::check(
        &plan.model,
        &plan.angle,
        plan.torque.as_deref(),
        plan.json.dt_s,
    )
}

//! An infeasible constrained cycle, said in terms of the plan: which slices, which feet would have
//! to pull or need more friction, which joints would exceed their limit, and what would make it
//! feasible. The solver's status ("infeasible", "almost solved") says none of that.

use super::report::{ConstraintReport, check_slice};
use super::{DynamicsError, DynamicsOptions, SliceInput};
use crate::model::Model;

/// Explains why `failed` slices (solver failures with constraints on) have no solution, from the
/// unconstrained optimum of each: feet that pull or leave the cone, joints over their limit.
/// Returns `original` when the unconstrained problem fails too (then it is not the constraints).
pub(super) fn diagnose(
    model: &Model,
    inputs: &[SliceInput],
    options: &DynamicsOptions,
    limits: &[Option<f64>],
    failed: &[usize],
    original: DynamicsError,
) -> DynamicsError {
    let free = DynamicsOptions {
        push_only: false,
        friction_cone: false,
        enforce_torque_limits: false,
        parallel: false,
        ..options.clone()
    };
    let mut report = ConstraintReport::default();
    for &s in failed {
        match super::solve_slice(model, &inputs[s], &free, s) {
            Ok(sol) => check_slice(model, s, &inputs[s], &sol, options.mu, limits, &mut report),
            Err(_) => return original,
        }
    }
    let contact = options.push_only || options.friction_cone;
    let mut feet: Vec<(String, f64, f64)> = Vec::new(); // leg, most negative normal, largest mu needed
    for slip in report.slips.iter().filter(|_| contact) {
        let mu = if slip.normal > 0.0 {
            slip.tangential / slip.normal
        } else {
            f64::INFINITY
        };
        match feet.iter_mut().find(|f| f.0 == slip.leg) {
            Some(f) => {
                f.1 = f.1.min(slip.normal);
                f.2 = f.2.max(mu);
            }
            None => feet.push((slip.leg.clone(), slip.normal.min(0.0), mu)),
        }
    }
    let mut joints: Vec<(String, f64, f64)> = Vec::new(); // joint, largest |torque|, limit
    for sat in report
        .saturations
        .iter()
        .filter(|_| options.enforce_torque_limits)
    {
        match joints.iter_mut().find(|j| j.0 == sat.joint) {
            Some(j) => j.1 = j.1.max(sat.torque.abs()),
            None => joints.push((sat.joint.clone(), sat.torque.abs(), sat.limit)),
        }
    }
    let mut need = Vec::new();
    let mut advice = Vec::new();
    let pulling: Vec<String> = feet
        .iter()
        .filter(|f| f.1 < 0.0)
        .map(|f| format!("{} pulls with up to {} N", f.0, num(-f.1)))
        .collect();
    if !pulling.is_empty() {
        need.push(pulling.join(", "));
        advice.push(
            "the stance feet cannot hold the body by pushing (its weight falls outside their support): \
             a lower body height, a smaller incline, a wider stance (placement) or more feet in stance",
        );
    }
    let sliding: Vec<String> = feet
        .iter()
        .filter(|f| f.1 >= 0.0 && options.friction_cone)
        .map(|f| format!("{} needs mu {:.2}", f.0, f.2))
        .collect();
    if !sliding.is_empty() {
        let mu = feet
            .iter()
            .filter(|f| f.2.is_finite())
            .fold(0.0f64, |m, f| m.max(f.2));
        need.push(format!(
            "{} (mu = {} given)",
            sliding.join(", "),
            options.mu
        ));
        advice.push(if mu.is_finite() && mu > 0.0 {
            "more friction (the unconstrained optimum fits in a cone of the largest mu named), a smaller incline or a lower body height"
        } else {
            "more friction, a smaller incline or a lower body height"
        });
    }
    if !joints.is_empty() {
        need.push(
            joints
                .iter()
                .map(|j| format!("{} needs {} N m (limit {})", j.0, num(j.1), num(j.2)))
                .collect::<Vec<_>>()
                .join(", "),
        );
        advice.push(
            "stronger actuators or less load: a lower body height, a slower step (a longer swing: --swing, Python: swing_s=) or no torque limits",
        );
    }
    if need.is_empty() {
        // The unconstrained optimum meets every constraint: the solver stopped at the boundary.
        need.push("the unconstrained optimum meets every constraint only at their boundary".into());
        advice.push("a little margin: slightly more friction or a lower body height");
    }
    let mut constraints = Vec::new();
    if options.push_only || options.friction_cone {
        constraints.push("push-only feet");
    }
    if options.friction_cone {
        constraints.push("friction cones");
    }
    if options.enforce_torque_limits {
        constraints.push("torque limits");
    }
    DynamicsError::Infeasible {
        slices: ranges(failed),
        constraints: constraints.join(" + "),
        need: need.join("; "),
        advice: advice.join("; or "),
    }
}

/// `[10, 11, 12, 14, 60, 61]` as `10-12, 14, 60-61`.
pub fn ranges(slices: &[usize]) -> String {
    let mut out: Vec<String> = Vec::new();
    let mut i = 0;
    while i < slices.len() {
        let mut k = i;
        while k + 1 < slices.len() && slices[k + 1] == slices[k] + 1 {
            k += 1;
        }
        out.push(if k == i {
            slices[i].to_string()
        } else {
            format!("{}-{}", slices[i], slices[k])
        });
        i = k + 1;
    }
    out.join(", ")
}

/// Robot-sized values in plain decimals, fly-sized ones (uN, nN m) in exponent form.
fn num(x: f64) -> String {
    if x.abs() >= 1e-2 {
        format!("{x:.3}")
    } else {
        format!("{x:.3e}")
    }
}

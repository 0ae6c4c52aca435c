//! Which slices would make a foot slip (or pull) or an actuator saturate: the check to run when
//! the contact and torque constraints are off, to see whether they matter.

use super::SliceInput;
use super::SliceSolution;
use crate::model::Model;

/// A stance foot whose GRF leaves the friction cone or pulls on the ground.
#[derive(Debug, Clone, PartialEq)]
pub struct Slip {
    pub slice: usize,
    pub leg: String,
    /// Normal component of the GRF, N (negative: the foot pulls).
    pub normal: f64,
    /// Magnitude of the tangential component, N.
    pub tangential: f64,
}

/// An actuated joint asked for more than its torque limit.
#[derive(Debug, Clone, PartialEq)]
pub struct Saturation {
    pub slice: usize,
    pub joint: String,
    /// N m.
    pub torque: f64,
    pub limit: f64,
}

/// All slips and saturations of a cycle.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ConstraintReport {
    pub slips: Vec<Slip>,
    pub saturations: Vec<Saturation>,
}

/// Relative slack so that solutions sitting on a constraint (solved with it on) are not reported.
const SLACK: f64 = 1e-6;

pub(super) fn check_slice(
    model: &Model,
    slice: usize,
    input: &SliceInput,
    s: &SliceSolution,
    mu: f64,
    limits: &[Option<f64>],
    report: &mut ConstraintReport,
) {
    for (i, foot) in model.feet.iter().enumerate() {
        if !input.stance[i] {
            continue;
        }
        let n = input.normals[i].normalize();
        let g = s.grf[i];
        let normal = n.dot(&g);
        let tangential = (g - n * normal).norm();
        let tol = SLACK * g.norm();
        if normal < -tol || tangential > mu * normal + tol {
            report.slips.push(Slip {
                slice,
                leg: foot.leg.name().into(),
                normal,
                tangential,
            });
        }
    }
    for (j, joint) in model.joints.iter().enumerate() {
        if let Some(limit) = limits.get(j).copied().flatten()
            && s.torque[j].abs() > limit * (1.0 + SLACK)
        {
            report.saturations.push(Saturation {
                slice,
                joint: joint.name.clone(),
                torque: s.torque[j],
                limit,
            });
        }
    }
}

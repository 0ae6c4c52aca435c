//! Newton-Euler per body (right side of paper eq. 7) and the backward pass that turns body wrenches
//! and ground reaction forces into joint forces and moments (the building blocks of eq. 8).

use nalgebra::Vector3;

use super::motion::BodyMotion;
use crate::model::Model;

/// Net force (N) and moment about the CoM (N m) that the rest of the world, gravity excluded,
/// must exert on each body: `m (a - g)` and `I alpha + w x I w`.
pub fn required_wrenches(
    model: &Model,
    motions: &[BodyMotion],
    gravity: &Vector3<f64>,
) -> Vec<(Vector3<f64>, Vector3<f64>)> {
    model
        .bodies
        .iter()
        .zip(motions)
        .map(|(b, m)| {
            let inertia = m.rotation * b.inertia * m.rotation.transpose();
            let force = b.mass * (m.com_acceleration - gravity);
            let moment = inertia * m.alpha + m.omega.cross(&(inertia * m.omega));
            (force, moment)
        })
        .collect()
}

/// Joint forces and moments plus what is left over at the thorax.
#[derive(Debug, Clone, PartialEq)]
pub struct JointWrenches {
    /// Force the parent exerts on the child at each joint, N.
    pub force: Vec<Vector3<f64>>,
    /// Moment the parent exerts on the child about the joint origin, N m.
    pub moment: Vec<Vector3<f64>>,
    /// Force and moment (about the thorax origin) that must still act on the thorax from outside
    /// the feet: zero for a floating body in equilibrium, the stand's load for a fixed base.
    pub base_force: Vector3<f64>,
    pub base_moment: Vector3<f64>,
}

/// Backward pass. `foot_forces[i]` is the GRF on foot `i` (zero for swing feet).
pub fn backward_pass(
    model: &Model,
    motions: &[BodyMotion],
    required: &[(Vector3<f64>, Vector3<f64>)],
    foot_forces: &[Vector3<f64>],
) -> JointWrenches {
    // Accumulated wrench each body needs from its proximal joint, moment about the body origin.
    let mut force: Vec<Vector3<f64>> = required.iter().map(|w| w.0).collect();
    let mut moment: Vec<Vector3<f64>> = required
        .iter()
        .zip(motions)
        .map(|(w, m)| w.1 + (m.com - m.origin).cross(&w.0))
        .collect();
    for (foot, g) in model.feet.iter().zip(foot_forces) {
        let m = &motions[foot.body];
        let p = m.origin + m.rotation * foot.point;
        force[foot.body] -= g;
        moment[foot.body] -= (p - m.origin).cross(g);
    }
    let n = model.joints.len();
    let mut jf = vec![Vector3::zeros(); n];
    let mut jm = vec![Vector3::zeros(); n];
    for (j, joint) in model.joints.iter().enumerate().rev() {
        let (c, p) = (joint.child, joint.parent);
        jf[j] = force[c];
        jm[j] = moment[c];
        let lever = motions[c].origin - motions[p].origin;
        force[p] += jf[j];
        moment[p] += jm[j] + lever.cross(&jf[j]);
    }
    JointWrenches {
        force: jf,
        moment: jm,
        base_force: force[0],
        base_moment: moment[0],
    }
}

/// Position of every foot's contact point in the thorax frame.
pub fn foot_positions(model: &Model, motions: &[BodyMotion]) -> Vec<Vector3<f64>> {
    model
        .feet
        .iter()
        .map(|f| {
            let m = &motions[f.body];
            m.origin + m.rotation * f.point
        })
        .collect()
}

//! The reduced per-slice problem: unknowns are the GRF of the stance feet, actuated torques are
//! affine in them, the thorax equilibrium gives 6 equalities, and the cost is V* (paper eq. 9).
//!
//! The QP is scaled to unit size (forces by the load, lengths by the foot spread, torques by
//! their product) so that solver tolerances mean the same thing for a 3 kg robot and a 1 mg fly.

use nalgebra::{DMatrix, DVector, Vector3};

use super::motion::{BodyMotion, body_motions};
use super::wrench::{JointWrenches, backward_pass, foot_positions, required_wrenches};
use super::{Base, DynamicsError, DynamicsOptions, SliceInput};
use crate::model::{Actuation, Model};
use crate::qp::{ConeBlock, QpProblem};

/// Joint stiffness k = actuator stiffness + parallel spring stiffness (N m/rad) of every joint;
/// `None` for fixed joints. See [`crate::model::spring`] for the names.
pub fn joint_stiffness(model: &Model) -> Result<Vec<Option<f64>>, DynamicsError> {
    model
        .joints
        .iter()
        .map(|j| match &j.actuation {
            Actuation::Fixed { .. } => Ok(None),
            Actuation::Actuated { stiffness, .. } => {
                let k = stiffness + j.spring.map_or(0.0, |s| s.stiffness);
                if k > 0.0 && k.is_finite() {
                    Ok(Some(k))
                } else {
                    Err(DynamicsError::Stiffness {
                        joint: j.name.clone(),
                        stiffness: k,
                    })
                }
            }
        })
        .collect()
}

/// Torque of each joint's parallel spring, -k_s (q - q_eq), N m (zero without a spring).
pub fn spring_torques(model: &Model, q: &[f64]) -> Vec<f64> {
    model
        .joints
        .iter()
        .zip(q)
        .map(|(j, &q)| j.spring.map_or(0.0, |s| -s.stiffness * (q - s.equilibrium)))
        .collect()
}

/// One slice's QP together with what is needed to turn its solution back into physics.
#[derive(Debug, Clone)]
pub struct SliceProblem {
    /// The scaled QP in the unknowns x~ = GRF / `force_scale`, stance feet in order, 3 each.
    pub qp: QpProblem,
    /// Indices (into `model.feet`) of the stance feet.
    pub stance: Vec<usize>,
    /// N per unit of x~.
    pub force_scale: f64,
    /// V* in J per unit of the scaled objective.
    pub cost_scale: f64,
    /// Constant of the scaled objective (its value at x~ = 0 is this).
    pub cost_constant: f64,
    pub motions: Vec<BodyMotion>,
    pub required: Vec<(Vector3<f64>, Vector3<f64>)>,
    /// Joint wrenches with all GRF zero.
    pub unloaded: JointWrenches,
    pub feet: Vec<Vector3<f64>>,
}

impl SliceProblem {
    /// GRF per foot of the model (swing feet exactly zero) from a QP solution x~.
    pub fn foot_forces(&self, n_feet: usize, x: &DVector<f64>) -> Vec<Vector3<f64>> {
        let mut out = vec![Vector3::zeros(); n_feet];
        for (k, &i) in self.stance.iter().enumerate() {
            out[i] = Vector3::new(x[3 * k], x[3 * k + 1], x[3 * k + 2]) * self.force_scale;
        }
        out
    }
}

/// Which joints lie on the path from each foot's body to the thorax.
fn joints_above(model: &Model, body: usize) -> Vec<usize> {
    let mut out = Vec::new();
    let mut b = body;
    while b != 0 {
        match model.joints.iter().position(|j| j.child == b) {
            Some(j) => {
                out.push(j);
                b = model.joints[j].parent;
            }
            None => break,
        }
    }
    out
}

/// Build the QP of one slice. `stiffness` is [`joint_stiffness`], `limits` the resolved torque limits.
pub fn build(
    model: &Model,
    input: &SliceInput,
    options: &DynamicsOptions,
    stiffness: &[Option<f64>],
    limits: &[Option<f64>],
) -> SliceProblem {
    let motions = body_motions(model, input);
    let required = required_wrenches(model, &motions, &input.gravity);
    let zero = vec![Vector3::zeros(); model.feet.len()];
    let unloaded = backward_pass(model, &motions, &required, &zero);
    let feet = foot_positions(model, &motions);
    let stance: Vec<usize> = (0..model.feet.len()).filter(|&i| input.stance[i]).collect();
    let n = 3 * stance.len();

    let weight: f64 = model.bodies.iter().map(|b| b.mass).sum::<f64>() * input.gravity.norm();
    let force_scale = positive_or_one(weight + unloaded.base_force.norm());
    let length_scale = positive_or_one(
        feet.iter()
            .chain(motions.iter().map(|m| &m.origin))
            .map(|p| p.norm())
            .fold(0.0, f64::max),
    );
    let torque_scale = force_scale * length_scale;

    // Actuated torques T = c + B x (N m, x in N), scaled: T / torque_scale = c~ + B~ x~.
    let springs = spring_torques(model, &input.q);
    let actuated: Vec<usize> = (0..model.joints.len())
        .filter(|&j| stiffness[j].is_some())
        .collect();
    let k_ref = actuated
        .iter()
        .map(|&j| stiffness[j].unwrap_or(1.0))
        .sum::<f64>()
        / actuated.len().max(1) as f64;
    let mut c = DVector::zeros(actuated.len());
    let mut bt = DMatrix::zeros(actuated.len(), n);
    let mut w = DVector::zeros(actuated.len());
    for (a, &j) in actuated.iter().enumerate() {
        let u = motions[model.joints[j].child].axis;
        c[a] = (u.dot(&unloaded.moment[j]) - springs[j]) / torque_scale;
        w[a] = k_ref / stiffness[j].unwrap_or(k_ref);
    }
    for (k, &i) in stance.iter().enumerate() {
        for j in joints_above(model, model.feet[i].body) {
            if let Some(a) = actuated.iter().position(|&x| x == j) {
                let o = motions[model.joints[j].child].origin;
                let u = motions[model.joints[j].child].axis;
                let row = -u.cross(&(feet[i] - o)) / length_scale;
                bt.view_mut((a, 3 * k), (1, 3)).copy_from(&row.transpose());
            }
        }
    }
    let wb = DMatrix::from_diagonal(&w) * &bt;
    let p = bt.transpose() * &wb;
    let q = wb.transpose() * &c;
    let cost_constant = 0.5 * c.dot(&w.component_mul(&c));

    let mut rows: Vec<DVector<f64>> = Vec::new();
    let mut rhs: Vec<f64> = Vec::new();
    let mut cones = Vec::new();
    if options.base == Base::Floating {
        for axis in 0..3 {
            let mut r = DVector::zeros(n);
            for k in 0..stance.len() {
                r[3 * k + axis] = 1.0;
            }
            rows.push(r);
            rhs.push(unloaded.base_force[axis] / force_scale);
        }
        for axis in 0..3 {
            let mut r = DVector::zeros(n);
            for (k, &i) in stance.iter().enumerate() {
                // (p x G)_axis = (e_axis x ... ) : row of skew(p).
                let s = feet[i].cross_matrix() / length_scale;
                r.rows_mut(3 * k, 3).copy_from(&s.row(axis).transpose());
            }
            rows.push(r);
            rhs.push(unloaded.base_moment[axis] / torque_scale);
        }
        cones.push(ConeBlock::Zero(6));
    }
    let mut nonneg = 0;
    if options.push_only && !options.friction_cone {
        for (k, &i) in stance.iter().enumerate() {
            let nrm = input.normals[i].normalize();
            let mut r = DVector::zeros(n);
            r.rows_mut(3 * k, 3).copy_from(&(-nrm));
            rows.push(r);
            rhs.push(0.0);
            nonneg += 1;
        }
    }
    if options.enforce_torque_limits {
        for (a, &j) in actuated.iter().enumerate() {
            if let Some(lim) = limits[j] {
                let lim = lim / torque_scale;
                rows.push(bt.row(a).transpose());
                rhs.push(lim - c[a]);
                rows.push(-bt.row(a).transpose());
                rhs.push(lim + c[a]);
                nonneg += 2;
            }
        }
    }
    if nonneg > 0 {
        cones.push(ConeBlock::Nonnegative(nonneg));
    }
    if options.friction_cone {
        for (k, &i) in stance.iter().enumerate() {
            let nrm = input.normals[i].normalize();
            let (t1, t2) = tangents(&nrm);
            for v in [nrm * options.mu, t1, t2] {
                let mut r = DVector::zeros(n);
                r.rows_mut(3 * k, 3).copy_from(&(-v));
                rows.push(r);
                rhs.push(0.0);
            }
            cones.push(ConeBlock::SecondOrder(3));
        }
    }
    let mut a = DMatrix::zeros(rows.len(), n);
    for (i, r) in rows.iter().enumerate() {
        a.set_row(i, &r.transpose());
    }
    SliceProblem {
        qp: QpProblem {
            p,
            q,
            a,
            b: DVector::from_vec(rhs),
            cones,
        },
        stance,
        force_scale,
        cost_scale: torque_scale * torque_scale / k_ref,
        cost_constant,
        motions,
        required,
        unloaded,
        feet,
    }
}

fn positive_or_one(x: f64) -> f64 {
    if x > 0.0 && x.is_finite() { x } else { 1.0 }
}

/// Two unit vectors completing `n` (unit) to a right-handed orthonormal basis.
pub fn tangents(n: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let helper = if n.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let t1 = n.cross(&helper).normalize();
    (t1, n.cross(&t1))
}

//! Independent truth: recursive Newton-Euler with 6D spatial vectors in body coordinates
//! (Featherstone, "Rigid Body Dynamics Algorithms", table 5.1), gravity as a fictitious base
//! acceleration, external foot forces subtracted per body. Written from the textbook, not from
//! `planner::dynamics` (which works with 3D vectors in the thorax frame and builds a QP).

use nalgebra::{Matrix3, Vector3};
use planner::model::Model;

type V3 = Vector3<f64>;

/// A spatial vector as (angular, linear) parts.
#[derive(Debug, Clone, Copy)]
pub struct Sv(pub V3, pub V3);

/// Motion of the base (thorax) expressed in its own frame.
#[derive(Debug, Clone, Copy, Default)]
pub struct BaseState {
    pub omega: V3,
    pub alpha: V3,
    pub velocity: V3,
    /// Classical acceleration of the thorax origin.
    pub acceleration: V3,
}

/// Per body: world (thorax-frame) rotation and origin, spatial velocity and acceleration in
/// body coordinates.
#[derive(Debug, Clone)]
pub struct Kin {
    pub rot: Vec<Matrix3<f64>>,
    pub pos: Vec<V3>,
    pub vel: Vec<Sv>,
    pub acc: Vec<Sv>,
}

/// Rodrigues' formula, written out.
pub fn rodrigues(axis: &V3, angle: f64) -> Matrix3<f64> {
    let k = axis / axis.norm();
    let kx = Matrix3::new(0.0, -k.z, k.y, k.z, 0.0, -k.x, -k.y, k.x, 0.0);
    Matrix3::identity() + kx * angle.sin() + kx * kx * (1.0 - angle.cos())
}

fn cross_motion(a: Sv, b: Sv) -> Sv {
    Sv(a.0.cross(&b.0), a.0.cross(&b.1) + a.1.cross(&b.0))
}

fn cross_force(a: Sv, f: Sv) -> Sv {
    Sv(a.0.cross(&f.0) + a.1.cross(&f.1), a.0.cross(&f.1))
}

/// Forward pass. `gravity` enters as base acceleration -g (pass zero to get true accelerations).
pub fn forward(
    model: &Model,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    base: BaseState,
    gravity: V3,
) -> Kin {
    let n = model.bodies.len();
    let mut k = Kin {
        rot: vec![Matrix3::identity(); n],
        pos: vec![V3::zeros(); n],
        vel: vec![Sv(V3::zeros(), V3::zeros()); n],
        acc: vec![Sv(V3::zeros(), V3::zeros()); n],
    };
    k.vel[0] = Sv(base.omega, base.velocity);
    // Spatial acceleration of the base: classical minus w x v, then the fictitious -g.
    k.acc[0] = Sv(
        base.alpha,
        base.acceleration - base.omega.cross(&base.velocity) - gravity,
    );
    for (i, j) in model.joints.iter().enumerate() {
        let parent_to_joint =
            j.origin.rotation.to_rotation_matrix().into_inner() * rodrigues(&j.axis, q[i]);
        let e = parent_to_joint.transpose();
        let r = j.origin.translation.vector;
        let xm = |m: Sv| Sv(e * m.0, e * (m.1 - r.cross(&m.0)));
        let s = Sv(j.axis.into_inner(), V3::zeros());
        let vp = k.vel[j.parent];
        let ap = k.acc[j.parent];
        let xv = xm(vp);
        let v = Sv(xv.0 + s.0 * qd[i], xv.1);
        let xa = xm(ap);
        let sqd = Sv(s.0 * qd[i], V3::zeros());
        let c = cross_motion(v, sqd);
        k.vel[j.child] = v;
        k.acc[j.child] = Sv(xa.0 + s.0 * qdd[i] + c.0, xa.1 + c.1);
        k.rot[j.child] = k.rot[j.parent] * parent_to_joint;
        k.pos[j.child] = k.pos[j.parent] + k.rot[j.parent] * r;
    }
    k
}

/// Spatial inertia of body `b` about its frame origin applied to motion `m`.
fn inertia_times(model: &Model, b: usize, m: Sv) -> Sv {
    let body = &model.bodies[b];
    let c = body.com;
    let mass = body.mass;
    let cx = c.cross_matrix();
    let i_o = body.inertia + mass * cx * cx.transpose();
    Sv(
        i_o * m.0 + mass * c.cross(&m.1),
        mass * m.1 - mass * c.cross(&m.0),
    )
}

/// Result of the full RNEA with external foot forces.
#[derive(Debug, Clone)]
pub struct Rnea {
    /// Axis moment per joint, N m.
    pub tau: Vec<f64>,
    /// Force and moment (about the joint origin) parent on child, thorax frame.
    pub force: Vec<V3>,
    pub moment: Vec<V3>,
    /// Wrench still needed at the thorax (zero if the feet hold it), thorax frame.
    pub base: Sv,
}

/// Inverse dynamics at the angles `q` of the motion `k` (their [`forward`] pass) with the foot forces `grf` (thorax
/// frame) applied at the feet.
pub fn rnea(model: &Model, q: &[f64], k: &Kin, grf: &[V3]) -> Rnea {
    let n = model.bodies.len();
    let mut f: Vec<Sv> = (0..n)
        .map(|b| {
            let ia = inertia_times(model, b, k.acc[b]);
            let iv = inertia_times(model, b, k.vel[b]);
            let g = cross_force(k.vel[b], iv);
            Sv(ia.0 + g.0, ia.1 + g.1)
        })
        .collect();
    for (foot, g) in model.feet.iter().zip(grf) {
        let gb = k.rot[foot.body].transpose() * g;
        f[foot.body].0 -= foot.point.cross(&gb);
        f[foot.body].1 -= gb;
    }
    let nj = model.joints.len();
    let mut out = Rnea {
        tau: vec![0.0; nj],
        force: vec![V3::zeros(); nj],
        moment: vec![V3::zeros(); nj],
        base: Sv(V3::zeros(), V3::zeros()),
    };
    for (i, j) in model.joints.iter().enumerate().rev() {
        let fi = f[j.child];
        out.tau[i] = j.axis.dot(&fi.0);
        out.moment[i] = k.rot[j.child] * fi.0;
        out.force[i] = k.rot[j.child] * fi.1;
        let parent_to_joint =
            j.origin.rotation.to_rotation_matrix().into_inner() * rodrigues(&j.axis, q[i]);
        let r = j.origin.translation.vector;
        let et = parent_to_joint; // E^T
        let fp = Sv(et * fi.0 + r.cross(&(et * fi.1)), et * fi.1);
        f[j.parent].0 += fp.0;
        f[j.parent].1 += fp.1;
    }
    out.base = f[0];
    out
}

/// Rate of change of linear momentum and of angular momentum about the thorax origin, computed
/// from the true (gravity-free) accelerations, thorax frame.
pub fn momentum_rate(
    model: &Model,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    base: BaseState,
) -> (V3, V3) {
    let k = forward(model, q, qd, qdd, base, V3::zeros());
    let mut lin = V3::zeros();
    let mut ang = V3::zeros();
    for (b, body) in model.bodies.iter().enumerate() {
        let (w, v) = (k.vel[b].0, k.vel[b].1);
        let (al, asp) = (k.acc[b].0, k.acc[b].1);
        let c = body.com;
        let a_origin = asp + w.cross(&v);
        let a_com = k.rot[b] * (a_origin + al.cross(&c) + w.cross(&w.cross(&c)));
        let p_com = k.pos[b] + k.rot[b] * c;
        lin += body.mass * a_com;
        ang += p_com.cross(&(body.mass * a_com))
            + k.rot[b] * (body.inertia * al + w.cross(&(body.inertia * w)));
    }
    (lin, ang)
}

/// World (thorax-frame) CoM of every body, for finite differences.
pub fn com_positions(model: &Model, q: &[f64]) -> Vec<V3> {
    let z = vec![0.0; q.len()];
    let k = forward(model, q, &z, &z, BaseState::default(), V3::zeros());
    model
        .bodies
        .iter()
        .enumerate()
        .map(|(b, body)| k.pos[b] + k.rot[b] * body.com)
        .collect()
}

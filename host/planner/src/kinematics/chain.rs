//! One leg as a fixed-size serial chain, and its inverse kinematics: Newton / damped least squares
//! on the foot position, with the spare degrees of freedom of redundant legs pulled to a rest
//! posture in the null space (so the answer depends on the target, not on the path, and a periodic
//! footpath gives periodic angles), joint limits enforced by clamping.

use super::{KinematicsError, MAX_CHAIN};
use crate::model::{Actuation, Leg, Model};
use nalgebra::{Isometry3, Matrix3, Point3, Unit, UnitQuaternion, Vector3};

/// Tolerances of the leg IK.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IkOptions {
    /// Foot position tolerance as a fraction of the leg length.
    pub tol_rel: f64,
    /// Tolerance on the null-space (rest-posture) step, rad.
    pub tol_null: f64,
    pub max_iter: usize,
}

impl Default for IkOptions {
    fn default() -> Self {
        IkOptions {
            tol_rel: 1e-9,
            tol_null: 1e-8,
            max_iter: 1000,
        }
    }
}

/// A leg from the thorax to its foot, with its actuated joints as the unknowns.
#[derive(Debug, Clone)]
pub struct LegChain {
    pub leg: Leg,
    /// `seg[k]`: constant transform from actuated joint k-1's turned frame (the thorax for k = 0)
    /// to actuated joint k's frame, fixed joints folded in.
    seg: [Isometry3<f64>; MAX_CHAIN],
    axes: [Unit<Vector3<f64>>; MAX_CHAIN],
    /// Model joint index of each actuated joint, proximal first.
    pub actuated: Vec<usize>,
    lo: [f64; MAX_CHAIN],
    hi: [f64; MAX_CHAIN],
    /// Foot point in the last actuated joint's turned frame.
    foot: Vector3<f64>,
    /// Leg length (m), the scale of the tolerances.
    pub length: f64,
}

impl LegChain {
    pub fn new(model: &Model, leg: Leg) -> Result<Self, KinematicsError> {
        let foot = model
            .foot(leg)
            .ok_or(KinematicsError::NoFoot { leg: leg.name() })?;
        let chain = model.leg_chain(leg);
        if chain.len() > MAX_CHAIN {
            return Err(KinematicsError::ChainTooLong {
                leg: leg.name(),
                len: chain.len(),
                max: MAX_CHAIN,
            });
        }
        let mut c = LegChain {
            leg,
            seg: [Isometry3::identity(); MAX_CHAIN],
            axes: [Vector3::x_axis(); MAX_CHAIN],
            actuated: Vec::new(),
            lo: [0.0; MAX_CHAIN],
            hi: [0.0; MAX_CHAIN],
            foot: foot.point,
            length: model.leg_length(leg),
        };
        let mut acc = Isometry3::identity();
        for &j in &chain {
            let joint = &model.joints[j];
            acc *= joint.origin;
            match joint.actuation {
                Actuation::Fixed { angle } => {
                    acc *= UnitQuaternion::from_axis_angle(&joint.axis, angle)
                }
                Actuation::Actuated { .. } => {
                    let a = c.actuated.len();
                    c.seg[a] = acc;
                    c.axes[a] = joint.axis;
                    c.lo[a] = joint.limits.0;
                    c.hi[a] = joint.limits.1;
                    c.actuated.push(j);
                    acc = Isometry3::identity();
                }
            }
        }
        c.foot = (acc * Point3::from(foot.point)).coords;
        Ok(c)
    }

    /// Number of unknowns (actuated joints).
    pub fn dof(&self) -> usize {
        self.actuated.len()
    }

    /// Joint limits of actuated joint `a`.
    pub fn limits(&self, a: usize) -> (f64, f64) {
        (self.lo[a], self.hi[a])
    }

    /// Foot position and, per actuated joint, its world position and axis.
    fn fk(
        &self,
        qa: &[f64],
    ) -> (
        Vector3<f64>,
        [Vector3<f64>; MAX_CHAIN],
        [Vector3<f64>; MAX_CHAIN],
    ) {
        let mut pose = Isometry3::identity();
        let mut o = [Vector3::zeros(); MAX_CHAIN];
        let mut a = [Vector3::zeros(); MAX_CHAIN];
        for k in 0..self.dof() {
            pose *= self.seg[k];
            o[k] = pose.translation.vector;
            a[k] = pose.rotation * self.axes[k].into_inner();
            pose *= UnitQuaternion::from_axis_angle(&self.axes[k], qa[k]);
        }
        ((pose * Point3::from(self.foot)).coords, o, a)
    }

    /// Foot position for the actuated angles `qa` (thorax frame).
    pub fn foot_position(&self, qa: &[f64]) -> Vector3<f64> {
        self.fk(qa).0
    }

    /// Position Jacobian (3 x dof) columns and the foot position.
    pub fn jacobian(&self, qa: &[f64]) -> (Vector3<f64>, [Vector3<f64>; MAX_CHAIN]) {
        let (p, o, a) = self.fk(qa);
        let mut jac = [Vector3::zeros(); MAX_CHAIN];
        for k in 0..self.dof() {
            jac[k] = a[k].cross(&(p - o[k]));
        }
        (p, jac)
    }

    /// Moves `qa` (warm start, updated in place) until the foot is at `target` within tolerance,
    /// pulling spare degrees of freedom towards `rest`. Returns the iterations used, or the
    /// remaining distance (m) if the target was not reached.
    // The loops walk several index-parallel fixed-size arrays (angles, limits, Jacobian columns).
    #[allow(clippy::needless_range_loop)]
    pub fn solve(
        &self,
        target: &Vector3<f64>,
        qa: &mut [f64],
        rest: &[f64],
        opts: &IkOptions,
    ) -> Result<usize, f64> {
        let m = self.dof();
        let tol = opts.tol_rel * self.length;
        let damping = (1e-6 * self.length).powi(2);
        let mut dist = f64::INFINITY;
        for it in 0..opts.max_iter {
            let (p, mut jac) = self.jacobian(qa);
            let e = target - p;
            dist = e.norm();
            // Active set: a joint at a limit that the step would push further is locked (its
            // column and its null-space share removed) and the step recomputed.
            let mut locked = [false; MAX_CHAIN];
            let mut dq = [0.0; MAX_CHAIN];
            let mut null_norm = 0.0;
            for _ in 0..=m {
                let mut a = Matrix3::zeros();
                for k in 0..m {
                    if locked[k] {
                        jac[k] = Vector3::zeros();
                    }
                    a += jac[k] * jac[k].transpose();
                }
                let Some(ainv) = (a + Matrix3::identity() * damping).try_inverse() else {
                    return Err(dist);
                };
                let y = ainv * e;
                for k in 0..m {
                    dq[k] = if locked[k] { 0.0 } else { jac[k].dot(&y) };
                }
                null_norm = 0.0;
                if m > 3 {
                    // Null-space pull towards rest: g - J^T (J J^T)^-1 J g.
                    let g = |k: usize| if locked[k] { 0.0 } else { rest[k] - qa[k] };
                    let mut jg = Vector3::zeros();
                    for k in 0..m {
                        jg += jac[k] * g(k);
                    }
                    let h = ainv * jg;
                    for k in 0..m {
                        let n = g(k) - jac[k].dot(&h);
                        null_norm += n * n;
                        dq[k] += n;
                    }
                    null_norm = null_norm.sqrt();
                }
                let mut newly = false;
                for k in 0..m {
                    let out = (qa[k] <= self.lo[k] && dq[k] < 0.0)
                        || (qa[k] >= self.hi[k] && dq[k] > 0.0);
                    if out && !locked[k] {
                        locked[k] = true;
                        newly = true;
                    }
                }
                if !newly {
                    break;
                }
            }
            if dist < tol && null_norm < opts.tol_null {
                return Ok(it);
            }
            // Newton steps far from the solution can overshoot wildly: cap the largest at 0.2 rad.
            let big = dq.iter().take(m).fold(0.0f64, |b, d| b.max(d.abs()));
            let scale = if big > 0.2 { 0.2 / big } else { 1.0 };
            for k in 0..m {
                qa[k] = (qa[k] + scale * dq[k]).clamp(self.lo[k], self.hi[k]);
            }
        }
        if dist < tol {
            Ok(opts.max_iter)
        } else {
            Err(dist)
        }
    }

    /// Solves a whole footpath, slice by slice from `start`; returns actuated angles per slice.
    pub fn solve_path(
        &self,
        targets: &[Vector3<f64>],
        start: &[f64],
        rest: &[f64],
        opts: &IkOptions,
    ) -> Result<Vec<Vec<f64>>, KinematicsError> {
        let mut q = start.to_vec();
        let mut out = Vec::with_capacity(targets.len());
        for (slice, t) in targets.iter().enumerate() {
            self.solve(t, &mut q, rest, opts)
                .map_err(|d| KinematicsError::unreachable(self.leg, slice, d))?;
            out.push(q.clone());
        }
        Ok(out)
    }
}

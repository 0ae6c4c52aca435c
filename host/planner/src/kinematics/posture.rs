//! The resting posture: the mid-point of every footpath.
//!
//! Flat ground (and an incline, on which the thorax stays parallel to the plane): each foot at the
//! leg pair's ground height below the thorax, with the leg's joints as close to mid-range as that
//! allows (minimum-norm Newton on the height with a null-space pull to mid-range). Ball: the flat
//! posture's x and y, projected down onto the sphere, then solved exactly.

use super::{IkOptions, KinematicsError, LegChain};
use crate::model::{Leg, Model};
use crate::terrain::Terrain;
use nalgebra::Vector3;

/// A resting posture: the full joint vector and each leg's foot position (thorax frame).
#[derive(Debug, Clone, PartialEq)]
pub struct Posture {
    /// One angle per model joint (fixed joints at their angle).
    pub q: Vec<f64>,
    /// Foot position per leg, [`Model::legs`] order.
    pub feet: Vec<(Leg, Vector3<f64>)>,
    /// Centre of a ball terrain: `offset_m` below the centre of mass of the flat posture.
    pub ball_centre: Option<Vector3<f64>>,
}

impl Posture {
    /// The resting foot position of a leg.
    pub fn foot(&self, leg: Leg) -> Option<Vector3<f64>> {
        self.feet.iter().find(|(l, _)| *l == leg).map(|(_, p)| *p)
    }
}

/// Solves the flat posture of one leg: foot at height `z`, joints near mid-range.
fn flat_leg(chain: &LegChain, mid: &[f64], z: f64) -> Result<Vec<f64>, KinematicsError> {
    let m = chain.dof();
    let mut q = mid.to_vec();
    let tol = 1e-10 * chain.length;
    for _ in 0..500 {
        let (p, jac) = chain.jacobian(&q);
        let e = z - p.z;
        let jz: Vec<f64> = jac.iter().take(m).map(|c| c.z).collect();
        let jj: f64 = jz.iter().map(|x| x * x).sum::<f64>() + (1e-6 * chain.length).powi(2);
        let jg: f64 = (0..m).map(|k| jz[k] * (mid[k] - q[k])).sum();
        let mut step = 0.0;
        for k in 0..m {
            let dq = jz[k] * e / jj + (mid[k] - q[k]) - jz[k] * jg / jj;
            step += dq * dq;
            let (lo, hi) = chain.limits(k);
            q[k] = (q[k] + dq).clamp(lo, hi);
        }
        if e.abs() < tol && step.sqrt() < 1e-10 {
            return Ok(q);
        }
    }
    let p = chain.foot_position(&q);
    if (p.z - z).abs() < tol {
        return Ok(q);
    }
    Err(KinematicsError::Posture {
        leg: chain.leg.name(),
        problem: format!(
            "cannot put the foot at height {z:.4} m (reached {:.4} m) within joint limits",
            p.z
        ),
    })
}

/// Where a resting foot should go on flat ground: at height `z` (m, thorax frame, negative below
/// the thorax), and optionally at `(forward, outward)` metres from the leg's ThC.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FootGoal {
    pub z: f64,
    pub from_thc: Option<(f64, f64)>,
}

/// The resting posture on `terrain` with the foot goals `goal(leg)` on flat ground.
pub fn resting_posture(
    model: &Model,
    terrain: &Terrain,
    goal: &dyn Fn(Leg) -> FootGoal,
) -> Result<Posture, KinematicsError> {
    let mut q = model.mid_range_q();
    let mid = q.clone();
    let mut feet = Vec::new();
    let mut chains = Vec::new();
    for leg in model.legs() {
        let chain = LegChain::new(model, leg)?;
        let mid_a: Vec<f64> = chain.actuated.iter().map(|&j| mid[j]).collect();
        let g = goal(leg);
        let mut qa = flat_leg(&chain, &mid_a, g.z)?;
        if let Some((fwd, out)) = g.from_thc {
            let thc = model.joints[model.leg_chain(leg)[0]]
                .origin
                .translation
                .vector;
            let target = Vector3::new(thc.x + fwd, thc.y + leg.side() * out, g.z);
            // Walk the foot there in small steps so that Newton stays in its basin.
            let start = chain.foot_position(&qa);
            for k in 1..20 {
                let t = start + (target - start) * (k as f64 / 20.0);
                let _ = chain.solve(&t, &mut qa, &mid_a, &IkOptions::default());
            }
            chain.solve(&target, &mut qa, &mid_a, &IkOptions::default()).map_err(|d| KinematicsError::Posture {
                leg: leg.name(),
                problem: format!("placement {fwd} m forward, {out} m outward of the ThC unreachable ({d:.3e} m away)"),
            })?;
        }
        for (k, &j) in chain.actuated.iter().enumerate() {
            q[j] = qa[k];
        }
        feet.push((leg, chain.foot_position(&qa)));
        chains.push((chain, qa));
    }
    let ball_centre = ball_centre(terrain, model, &q);
    if let (Terrain::Ball { radius_m, .. }, Some(centre)) = (terrain, ball_centre) {
        for ((chain, qa), (leg, foot)) in chains.iter_mut().zip(feet.iter_mut()) {
            let d = Vector3::new(foot.x - centre.x, foot.y - centre.y, 0.0);
            let h2 = radius_m * radius_m - d.norm_squared();
            if h2 <= 0.0 {
                return Err(KinematicsError::Posture {
                    leg: leg.name(),
                    problem: format!(
                        "foot at ({:.4}, {:.4}) m lies outside the ball of radius {radius_m} m",
                        foot.x, foot.y
                    ),
                });
            }
            let target = Vector3::new(foot.x, foot.y, centre.z + h2.sqrt());
            let rest = qa.clone();
            chain
                .solve(&target, qa, &rest, &IkOptions::default())
                .map_err(|d| KinematicsError::Posture {
                    leg: leg.name(),
                    problem: format!("ball contact point unreachable, {d:.3e} m away"),
                })?;
            for (k, &j) in chain.actuated.iter().enumerate() {
                q[j] = qa[k];
            }
            *foot = target;
        }
    }

    Ok(Posture {
        q,
        feet,
        ball_centre,
    })
}

/// Centre of a ball terrain: under the whole-body centre of mass at joint vector `q` (`None` on
/// other terrains).
fn ball_centre(terrain: &Terrain, model: &Model, q: &[f64]) -> Option<Vector3<f64>> {
    let Terrain::Ball { offset_m, .. } = terrain else {
        return None;
    };
    let poses = super::forward(model, q);
    let mut c = Vector3::zeros();
    for (b, pose) in model.bodies.iter().zip(&poses.bodies) {
        c += (pose * nalgebra::Point3::from(b.com)).coords * b.mass;
    }
    let m = model.total_mass();
    let c = if m > 0.0 { c / m } else { c };
    Some(Vector3::new(c.x, c.y, c.z - offset_m))
}

//! A planned step cycle: resting posture, footpaths, inverse kinematics per slice, and velocities
//! and accelerations by periodic central differences. The inverse dynamics adds torques and ground
//! reaction forces to a [`Plan`] afterwards.

pub mod continuity;
mod derivatives;
pub mod feasibility;
pub mod feasibility_summary;
pub mod finite;
pub mod gait_table;
pub mod table;

pub use derivatives::periodic_central_difference;

use crate::gait::{Footpath, GroundMotion, ParamError, StepParams};
use crate::kinematics::{FootGoal, IkOptions, KinematicsError, LegChain, Posture, resting_posture};
use crate::model::{Leg, Model};
use crate::terrain::{Terrain, TerrainError};
use nalgebra::Vector3;
use serde::Serialize;

/// Why a plan could not be made.
#[derive(Debug, thiserror::Error)]
pub enum PlanError {
    #[error(transparent)]
    Params(#[from] ParamError),
    #[error(transparent)]
    Terrain(#[from] TerrainError),
    #[error(transparent)]
    Kinematics(#[from] KinematicsError),
}

/// One step cycle, sampled in `slices` equal time slices of `dt` seconds.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Plan {
    #[serde(skip)]
    pub model: Model,
    pub params: StepParams,
    pub terrain: Terrain,
    /// Gravity in the thorax frame, m/s^2.
    pub gravity: Vector3<f64>,
    /// Centre of the ball (thorax frame) on ball terrain.
    pub ball_centre: Option<Vector3<f64>>,
    pub period_s: f64,
    pub dt: f64,
    /// Legs in the order of the per-leg vectors below.
    pub legs: Vec<Leg>,
    /// Start of each leg's cycle, fraction of the period.
    pub phases: Vec<f64>,
    #[serde(skip)]
    pub posture: Posture,
    /// Joint angles, rad: `q[slice][joint]`, model joint order (fixed joints at their angle).
    #[serde(skip)]
    pub q: Vec<Vec<f64>>,
    /// Joint velocities, rad/s (equation 1).
    #[serde(skip)]
    pub qd: Vec<Vec<f64>>,
    /// Joint accelerations, rad/s^2 (equation 2).
    #[serde(skip)]
    pub qdd: Vec<Vec<f64>>,
    /// `stance[slice][leg]`.
    #[serde(skip)]
    pub stance: Vec<Vec<bool>>,
    /// Foot targets `feet[slice][leg]`, thorax frame, m (met by `q` to the IK tolerance).
    #[serde(skip)]
    pub feet: Vec<Vec<Vector3<f64>>>,
    /// Thorax linear velocity over the ground, thorax frame, m/s (zero on a ball: the ball moves).
    pub thorax_velocity: Vector3<f64>,
    /// Thorax angular velocity, rad/s.
    pub thorax_angular_velocity: Vector3<f64>,
    /// Joint steps between slices that no continuous inverse-kinematics solution within the joint
    /// limits avoided ([`continuity`]); empty when every trajectory is continuous.
    pub ik_gaps: Vec<continuity::IkGap>,
}

impl Plan {
    /// Number of slices.
    pub fn slices(&self) -> usize {
        self.q.len()
    }
    /// Time of a slice, s.
    pub fn time(&self, slice: usize) -> f64 {
        slice as f64 * self.dt
    }
}

/// The footpaths of every leg for a model, parameters and resting posture.
pub fn footpaths(params: &StepParams, terrain: &Terrain, posture: &Posture) -> Vec<Footpath> {
    let motion = GroundMotion::new(terrain, params, posture.ball_centre);
    posture
        .feet
        .iter()
        .map(|(leg, rest)| Footpath::new(*leg, *rest, params, motion))
        .collect()
}

/// Plans one step cycle.
pub fn plan(model: &Model, params: &StepParams) -> Result<Plan, PlanError> {
    params.validate()?;
    let terrain = params
        .terrain
        .plan_terrain(params.ball_radius_m, params.ball_offset_m)?;
    let posture = resting_posture(model, &terrain, &|leg| params.foot_goal(leg))?;
    let paths = footpaths(params, &terrain, &posture);
    let n = params.slices;
    let dt = params.period_s() / n as f64;
    let legs: Vec<Leg> = paths.iter().map(|p| p.leg).collect();
    let mut feet = vec![Vec::with_capacity(legs.len()); n];
    let mut stance = vec![Vec::with_capacity(legs.len()); n];
    for s in 0..n {
        for p in &paths {
            let (x, st) = p.at(s as f64 * dt);
            feet[s].push(x);
            stance[s].push(st);
        }
    }
    let mut q = vec![posture.q.clone(); n];
    let opts = IkOptions::default();
    let mut ik_gaps = Vec::new();
    for (li, leg) in legs.iter().enumerate() {
        let chain = LegChain::new(model, *leg)?;
        let rest: Vec<f64> = chain.actuated.iter().map(|&j| posture.q[j]).collect();
        let targets: Vec<Vector3<f64>> = feet.iter().map(|f| f[li]).collect();
        let sol = chain.solve_path(&targets, &rest, &rest, &opts)?;
        let (sol, gaps) =
            continuity::make_continuous(model, &chain, &targets, sol, (params.swing_s, dt), &opts);
        ik_gaps.extend(gaps);
        for (s, qa) in sol.iter().enumerate() {
            for (k, &j) in chain.actuated.iter().enumerate() {
                q[s][j] = qa[k];
            }
        }
    }
    // Springs whose equilibrium is the resting posture (or the step's mid-range) get it now.
    let mut model = model.clone();
    crate::model::spring::resolve_equilibria(&mut model, &posture.q, &q);
    let qd = periodic_central_difference(&q, dt);
    let qdd = periodic_central_difference(&qd, dt);
    let (thorax_velocity, thorax_angular_velocity) = match terrain {
        Terrain::Ball { .. } => (Vector3::zeros(), Vector3::zeros()),
        Terrain::Flat | Terrain::Incline { .. } => (
            Vector3::new(params.translation_m / params.stance_s(), 0.0, 0.0),
            Vector3::new(0.0, 0.0, params.rotation_rad / params.stance_s()),
        ),
    };
    Ok(Plan {
        model,
        params: params.clone(),
        gravity: terrain.gravity(),
        ball_centre: posture.ball_centre,
        terrain,
        period_s: params.period_s(),
        dt,
        phases: paths.iter().map(|p| p.phase).collect(),
        legs,
        posture,
        q,
        qd,
        qdd,
        stance,
        feet,
        thorax_velocity,
        thorax_angular_velocity,
        ik_gaps,
    })
}

impl StepParams {
    /// The resting-posture goal of a leg's foot on flat ground.
    pub fn foot_goal(&self, leg: Leg) -> FootGoal {
        FootGoal {
            z: -self.body_height_m.get(leg),
            from_thc: self
                .placement
                .map(|p| (p.forward_m.get(leg), p.outward_m.get(leg))),
        }
    }
}

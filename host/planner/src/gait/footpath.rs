//! Footpaths in the thorax frame. During stance a foot rides on the ground, whose motion relative
//! to the thorax is a rigid motion: a translation (straight walking), a rotation about the
//! instantaneous centre (curves) or the ball's rotation about its centre. Stance is centred on the
//! resting posture. Swing joins lift-off to touch-down with quintics matching position, velocity and
//! acceleration of the stance at both ends: one for x, one for y, two for z meeting at the apex at
//! mid-swing (zero vertical velocity and acceleration there).

use super::{Quintic, StepParams};
use crate::model::Leg;
use crate::terrain::Terrain;
use nalgebra::{Rotation3, Vector3};

/// Motion of ground points seen from the thorax, constant over the cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GroundMotion {
    /// Every ground point moves with `velocity` (m/s).
    Translation { velocity: Vector3<f64> },
    /// Ground points turn about the axis through `centre` with angular velocity `omega` (rad/s).
    Rotation {
        centre: Vector3<f64>,
        omega: Vector3<f64>,
    },
}

impl GroundMotion {
    /// The ground motion for walking with `params` on `terrain` (`ball_centre` for a ball).
    pub fn new(
        terrain: &Terrain,
        params: &StepParams,
        ball_centre: Option<Vector3<f64>>,
    ) -> GroundMotion {
        let t_st = params.stance_s();
        let v = params.translation_m / t_st;
        let w = params.rotation_rad / t_st;
        let ball = match terrain {
            Terrain::Ball { radius_m, .. } => ball_centre.map(|c| (c, *radius_m)),
            Terrain::Flat | Terrain::Incline { .. } => None,
        };
        match ball {
            Some((c, radius_m)) => GroundMotion::Rotation {
                centre: c,
                // The ball's top moves backward at the walking speed; yaw turns it about z.
                omega: Vector3::new(0.0, -v / radius_m, -w),
            },
            None if w.abs() < 1e-12 => GroundMotion::Translation {
                velocity: Vector3::new(-v, 0.0, 0.0),
            },
            None => GroundMotion::Rotation {
                // Instantaneous centre of rotation of the thorax, left of it for a left turn.
                centre: Vector3::new(0.0, v / w, 0.0),
                omega: Vector3::new(0.0, 0.0, -w),
            },
        }
    }

    /// Where a ground point at `p` (time 0) is after `t` seconds.
    pub fn displace(&self, p: &Vector3<f64>, t: f64) -> Vector3<f64> {
        match self {
            GroundMotion::Translation { velocity } => p + velocity * t,
            GroundMotion::Rotation { centre, omega } => {
                centre + Rotation3::new(omega * t) * (p - centre)
            }
        }
    }

    /// Velocity of the ground point at `p`.
    pub fn velocity(&self, p: &Vector3<f64>) -> Vector3<f64> {
        match self {
            GroundMotion::Translation { velocity } => *velocity,
            GroundMotion::Rotation { centre, omega } => omega.cross(&(p - centre)),
        }
    }

    /// Acceleration of the ground point at `p`.
    pub fn acceleration(&self, p: &Vector3<f64>) -> Vector3<f64> {
        match self {
            GroundMotion::Translation { .. } => Vector3::zeros(),
            GroundMotion::Rotation { centre, omega } => omega.cross(&omega.cross(&(p - centre))),
        }
    }
}

/// One leg's foot trajectory over a step cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct Footpath {
    pub leg: Leg,
    /// Start of this leg's cycle as a fraction of the period.
    pub phase: f64,
    pub period: f64,
    pub stance: f64,
    pub rest: Vector3<f64>,
    pub motion: GroundMotion,
    x: Quintic,
    y: Quintic,
    z_up: Quintic,
    z_down: Quintic,
}

impl Footpath {
    pub fn new(
        leg: Leg,
        rest: Vector3<f64>,
        params: &StepParams,
        motion: GroundMotion,
    ) -> Footpath {
        let (t_st, t_sw) = (params.stance_s(), params.swing_s);
        let lo = motion.displace(&rest, 0.5 * t_st);
        let td = motion.displace(&rest, -0.5 * t_st);
        let (vlo, vtd) = (motion.velocity(&lo), motion.velocity(&td));
        let (alo, atd) = (motion.acceleration(&lo), motion.acceleration(&td));
        let q = |i: usize| Quintic::new(lo[i], vlo[i], alo[i], td[i], vtd[i], atd[i], t_sw);
        let apex = 0.5 * (lo.z + td.z) + params.step_height_m.get(leg);
        Footpath {
            leg,
            phase: params.gait.phase(leg),
            period: params.period_s(),
            stance: t_st,
            rest,
            motion,
            x: q(0),
            y: q(1),
            z_up: Quintic::new(lo.z, vlo.z, alo.z, apex, 0.0, 0.0, 0.5 * t_sw),
            z_down: Quintic::new(apex, 0.0, 0.0, td.z, vtd.z, atd.z, 0.5 * t_sw),
        }
    }

    /// Time since the start of this leg's own cycle at global time `t`.
    pub fn local_time(&self, t: f64) -> f64 {
        (t / self.period - self.phase).rem_euclid(1.0) * self.period
    }

    /// Foot position at global time `t` and whether the foot is in stance.
    pub fn at(&self, t: f64) -> (Vector3<f64>, bool) {
        let tau = self.local_time(t);
        if tau < self.stance {
            (
                self.motion.displace(&self.rest, tau - 0.5 * self.stance),
                true,
            )
        } else {
            let s = tau - self.stance;
            let half = 0.5 * (self.period - self.stance);
            let z = if s < half {
                self.z_up.eval(s).0
            } else {
                self.z_down.eval(s - half).0
            };
            (Vector3::new(self.x.eval(s).0, self.y.eval(s).0, z), false)
        }
    }
}

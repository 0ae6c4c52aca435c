//! [`Body`]: the simulated body's state as a typed value, what a physics robot knows and a board
//! cannot: the thorax's pose and velocity, each foot's contact force, contact and slip, and the
//! simulated time. Read from a [`Plant`] at any moment ([`Plant::body`]); between bus cycles the
//! plant rests at the start of the next cycle.
//!
//! World frame (REP-103: x forward at the start, y left, z up), SI units. Positions and velocities
//! are MuJoCo's from the forward pass before its last step (positions one 1 ms timestep behind
//! the joint angles, as in `WalkSample`).

use mujoco_rs::wrappers::mj_model::MjtObjBase;
use planner::model::Leg;

use crate::plant::Plant;

/// The thorax (the root body): pose and velocity in the world.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Thorax {
    /// Origin of the thorax frame, m.
    pub position_m: [f64; 3],
    /// Orientation, unit quaternion (w, x, y, z).
    pub orientation: [f64; 4],
    /// Velocity of the thorax frame's origin, m/s.
    pub velocity_m_s: [f64; 3],
    /// Angular velocity, rad/s, world axes.
    pub angular_velocity_rad_s: [f64; 3],
}

impl Thorax {
    /// Roll (about x), pitch (about y) and yaw (about z) of the orientation, rad (z-y-x Euler
    /// angles: yaw, then pitch, then roll).
    pub fn roll_pitch_yaw(&self) -> [f64; 3] {
        let [w, x, y, z] = self.orientation;
        let roll = (2.0 * (w * x + y * z)).atan2(1.0 - 2.0 * (x * x + y * y));
        let pitch = (2.0 * (w * y - z * x)).clamp(-1.0, 1.0).asin();
        let yaw = (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z));
        [roll, pitch, yaw]
    }
}

/// One foot's contact with the ground (or the ball).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Foot {
    pub leg: Leg,
    /// Force the ground exerts on the foot, world frame, N (zero in the air).
    pub force_n: [f64; 3],
    /// Whether the foot touches something with a pushing (non-zero) normal force.
    pub contact: bool,
    /// Speed of the foot's contact point along the surface, relative to the surface, m/s (0 in
    /// the air): how fast a loaded foot slides.
    pub slip_m_s: f64,
}

/// The body at one moment.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// Simulated time since power-on, s.
    pub time_s: f64,
    pub thorax: Thorax,
    /// The model's feet, in the model's order.
    pub feet: Vec<Foot>,
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

impl Plant {
    /// The body's state now.
    pub fn body(&self) -> Body {
        let (position_m, orientation) = self.thorax_pose();
        let v = self
            .data
            .object_velocity(MjtObjBase::mjOBJ_BODY, self.thorax, false);
        let thorax = Thorax {
            position_m,
            orientation,
            velocity_m_s: [v[3], v[4], v[5]],
            angular_velocity_rad_s: [v[0], v[1], v[2]],
        };
        let forces = self.foot_forces();
        let feet = self
            .feet
            .iter()
            .zip(forces)
            .map(|(&(leg, geom), (_, force_n))| {
                let (contact, slip_m_s) = self.slip(geom);
                Foot {
                    leg,
                    force_n,
                    contact,
                    slip_m_s,
                }
            })
            .collect();
        Body {
            time_s: self.time(),
            thorax,
            feet,
        }
    }

    /// Whether `geom` pushes on anything, and the tangential speed of its contact point relative
    /// to the other geom's surface at the contact with the largest normal force, m/s.
    fn slip(&self, geom: usize) -> (bool, f64) {
        let mut best: Option<(f64, f64)> = None;
        for (i, c) in self.data.contact().iter().enumerate() {
            let other = if c.geom[0] as usize == geom {
                c.geom[1] as usize
            } else if c.geom[1] as usize == geom {
                c.geom[0] as usize
            } else {
                continue;
            };
            let normal_n = self.data.contact_force(i)[0];
            if normal_n <= 0.0 || best.is_some_and(|(n, _)| n >= normal_n) {
                continue;
            }
            let at_point = |g: usize| {
                let v = self.data.object_velocity(MjtObjBase::mjOBJ_GEOM, g, false);
                let centre = self.data.geom_xpos()[g];
                let r = [0, 1, 2].map(|k| c.pos[k] - centre[k]);
                let w = cross([v[0], v[1], v[2]], r);
                [0, 1, 2].map(|k| v[3 + k] + w[k])
            };
            let (a, b) = (at_point(geom), at_point(other));
            let rel = [0, 1, 2].map(|k| a[k] - b[k]);
            let n = [c.frame[0], c.frame[1], c.frame[2]];
            let along = rel[0] * n[0] + rel[1] * n[1] + rel[2] * n[2];
            let t = [0, 1, 2].map(|k| rel[k] - along * n[k]);
            let speed = (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt();
            best = Some((normal_n, speed));
        }
        best.map_or((false, 0.0), |(_, s)| (true, s))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn thorax(orientation: [f64; 4]) -> Thorax {
        Thorax {
            position_m: [0.0; 3],
            orientation,
            velocity_m_s: [0.0; 3],
            angular_velocity_rad_s: [0.0; 3],
        }
    }

    #[test]
    fn roll_pitch_yaw_of_single_rotations() {
        // A rotation by a about axis u is (cos a/2, sin a/2 u).
        let a = 0.3f64;
        let (c, s) = ((a / 2.0).cos(), (a / 2.0).sin());
        for (q, want) in [
            ([c, s, 0.0, 0.0], [a, 0.0, 0.0]),
            ([c, 0.0, s, 0.0], [0.0, a, 0.0]),
            ([c, 0.0, 0.0, s], [0.0, 0.0, a]),
            ([1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0]),
        ] {
            let got = thorax(q).roll_pitch_yaw();
            for k in 0..3 {
                assert!((got[k] - want[k]).abs() < 1e-12, "{q:?}: {got:?}");
            }
        }
    }
}

//! Physical ranges of a model's numbers, checked on every model whatever its source (TOML,
//! .aproj, built-in), so that an absurd value is refused at load, naming the body or joint and
//! field, instead of planning NaN torques or failing later as a "singular pose" (issue #19).
//!
//! The bounds are estimates chosen far beyond anything that walks, from a fly (masses of 1e-22 to
//! 1e-6 kg, joint stiffness from 1e-6 N m/rad) to a large robot (the shared TypicalHexapod
//! project: a 1687 kg thorax): they only keep the arithmetic meaningful.

use super::error::{ModelError, field};
use super::types::{Actuation, Model};

/// Heaviest body, kg (an estimate with room: the shared TypicalHexapod.aproj's thorax is 1687 kg,
/// Drosophibot II weighs 5 kg in all).
pub const MAX_BODY_MASS_KG: f64 = 10_000.0;
/// Longest distance of a joint, centre of mass or foot from its body's origin, m.
pub const MAX_LENGTH_M: f64 = 10.0;
/// Range of an actuated joint's stiffness (servo or muscle), N m/rad: below the lower bound the
/// joint is no spring at all and the posture solve is singular.
pub const STIFFNESS_NM_PER_RAD: (f64, f64) = (1e-12, 1e6);
/// A foot's sliding friction coefficient: above 0 (a foot that cannot push does not walk) and at
/// most 5 (beyond any dry elastomer on a hard surface; MuJoCo takes any non-negative value).
pub const FOOT_FRICTION: (f64, f64) = (0.01, 5.0);
/// A foot's sliding friction when the model gives none: the MJCF export's historical contact
/// friction, with which a standing robot's feet were measured not to creep. ESTIMATE (sand
/// paper's, `physics::substrate::SANDPAPER_MU`).
pub const DEFAULT_FOOT_FRICTION: f64 = 1.5;

impl Model {
    /// The sliding friction coefficient between a foot and the ground: the model file's
    /// `foot_friction`, else [`DEFAULT_FOOT_FRICTION`] (an ESTIMATE).
    pub fn foot_friction(&self) -> f64 {
        self.foot_friction.unwrap_or(DEFAULT_FOOT_FRICTION)
    }
}

impl Model {
    /// Every mass, length and stiffness finite, of the right sign and within the ranges above.
    pub(crate) fn check_ranges(&self, file: &str) -> Result<(), ModelError> {
        let mut total = 0.0;
        for b in &self.bodies {
            let place = format!("body {}", b.name);
            if !(b.mass.is_finite() && (0.0..=MAX_BODY_MASS_KG).contains(&b.mass)) {
                return Err(field(
                    file,
                    place,
                    "mass",
                    format!("{} kg is not a mass in 0 ..= {MAX_BODY_MASS_KG} kg", b.mass),
                ));
            }
            total += b.mass;
            if !within(b.com.iter()) {
                return Err(field(file, place, "com", too_far(b.com.iter())));
            }
            if !b.inertia.iter().all(|x| x.is_finite()) {
                return Err(field(file, place, "inertia", "not finite"));
            }
        }
        if let Some(mu) = self.foot_friction {
            let (lo, hi) = FOOT_FRICTION;
            if !(mu.is_finite() && (lo..=hi).contains(&mu)) {
                return Err(field(
                    file,
                    "model",
                    "foot_friction",
                    format!("{mu} is not a sliding friction coefficient in {lo} ..= {hi}"),
                ));
            }
        }
        // Each mass is finite and >= 0 here, so the sum is too.
        if total <= 0.0 {
            return Err(field(file, "model", "mass", "the bodies weigh nothing"));
        }
        for j in &self.joints {
            let place = format!("joint {}", j.name);
            let t = j.origin.translation.vector;
            if !within(t.iter()) {
                return Err(field(file, &place, "origin", too_far(t.iter())));
            }
            if let Actuation::Actuated { stiffness, .. } = j.actuation {
                let (lo, hi) = STIFFNESS_NM_PER_RAD;
                if !(stiffness.is_finite() && (lo..=hi).contains(&stiffness)) {
                    return Err(field(
                        file,
                        &place,
                        "stiffness",
                        format!("{stiffness:e} N m/rad is outside {lo:e} ..= {hi:e} N m/rad"),
                    ));
                }
            }
            if let Some(s) = j.spring
                && !(s.stiffness.is_finite()
                    && (0.0..=STIFFNESS_NM_PER_RAD.1).contains(&s.stiffness))
            {
                return Err(field(
                    file,
                    &place,
                    "spring.stiffness",
                    format!("{} N m/rad is outside 0 ..= 1e6 N m/rad", s.stiffness),
                ));
            }
        }
        for f in &self.feet {
            if !within(f.point.iter()) {
                return Err(field(
                    file,
                    format!("foot {}", f.leg.name()),
                    "point",
                    too_far(f.point.iter()),
                ));
            }
        }
        Ok(())
    }
}

fn within<'a>(v: impl Iterator<Item = &'a f64>) -> bool {
    v.into_iter()
        .all(|x| x.is_finite() && x.abs() <= MAX_LENGTH_M)
}

fn too_far<'a>(v: impl Iterator<Item = &'a f64>) -> String {
    let v: Vec<String> = v.map(|x| x.to_string()).collect();
    format!(
        "[{}] m is not finite or farther than {MAX_LENGTH_M} m",
        v.join(", ")
    )
}

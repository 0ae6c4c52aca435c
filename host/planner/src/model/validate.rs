//! The one validation every model passes whatever its loader (TOML file, AnimatLab .aproj,
//! built-in): [`Model::validate`]. A loader checks its own syntax and fields; this checks what
//! only makes sense of the model as a whole and must hold for every source (issue #30): joint
//! limits that are an interval, bodies that are physically possible rigid bodies, a foot on every
//! leg that has joints, leg chains the kinematics can solve ([`Model::check_legs`]), numbers in
//! their physical ranges ([`Model::check_ranges`]) and servo dynamics in theirs
//! ([`Model::check_servo_dynamics`]).

use super::error::{ModelError, field};
use super::types::{Actuation, Leg, Model};

/// Relative slack of the inertia checks (of the largest principal moment): eigenvalues of a
/// symmetric 3x3 matrix carry rounding of about 1e-15 relative; a thin rod's principal moments
/// meet the triangle inequality with equality, so the slack must not refuse it.
const INERTIA_SLACK: f64 = 1e-9;

impl Model {
    /// Every check a model must pass before anything plans, exports or simulates it; `file`
    /// names the source in the error, which names the body, joint or leg and the field.
    pub(crate) fn validate(&self, file: &str) -> Result<(), ModelError> {
        self.check_limits(file)?;
        self.check_ranges(file)?;
        self.check_servo_dynamics(file)?;
        self.check_rigid_bodies(file)?;
        self.check_feet(file)?;
        self.check_legs(file)
    }

    /// Limits finite and ordered: an actuated joint needs a range to move in (`lo < hi`), a
    /// fixed joint's angle lies within its limits.
    fn check_limits(&self, file: &str) -> Result<(), ModelError> {
        for j in &self.joints {
            let place = format!("joint {}", j.name);
            let (lo, hi) = j.limits;
            let ordered = match j.actuation {
                Actuation::Actuated { .. } => lo < hi,
                Actuation::Fixed { .. } => lo <= hi,
            };
            if !(lo.is_finite() && hi.is_finite() && ordered) {
                return Err(field(
                    file,
                    place,
                    "limits",
                    format!(
                        "[{lo}, {hi}] rad is not a range of motion (two finite angles, lower below upper)"
                    ),
                ));
            }
            if let Actuation::Fixed { angle } = j.actuation
                && !(lo..=hi).contains(&angle)
            {
                return Err(field(
                    file,
                    place,
                    "fixed angle",
                    format!("{angle} rad is outside the limits [{lo}, {hi}] rad"),
                ));
            }
        }
        Ok(())
    }

    /// Each body a rigid body that can exist: a positive mass and an inertia tensor (about its
    /// centre of mass) that is symmetric positive definite with principal moments meeting the
    /// triangle inequality (each at most the sum of the other two, as for any mass
    /// distribution: I1 + I2 - I3 = 2 * integral of x3^2 dm >= 0).
    fn check_rigid_bodies(&self, file: &str) -> Result<(), ModelError> {
        for b in &self.bodies {
            let place = format!("body {}", b.name);
            if !(b.mass.is_finite() && b.mass > 0.0) {
                return Err(field(
                    file,
                    place,
                    "mass",
                    format!("{} kg: a body needs a mass above zero", b.mass),
                ));
            }
            let i = &b.inertia;
            if !i.iter().all(|x| x.is_finite()) {
                return Err(field(file, place, "inertia", "not finite"));
            }
            let scale = i.abs().max();
            if (i - i.transpose()).abs().max() > INERTIA_SLACK * scale {
                return Err(field(file, place, "inertia", "not a symmetric tensor"));
            }
            let mut m = i.symmetric_eigenvalues();
            m.as_mut_slice().sort_by(f64::total_cmp);
            let [m1, m2, m3] = [m[0], m[1], m[2]];
            if !(m1.is_finite() && m1 > 0.0) {
                return Err(field(
                    file,
                    place,
                    "inertia",
                    format!(
                        "principal moments {m1:e}, {m2:e}, {m3:e} kg m^2: not positive definite \
                         (every principal moment of a body must be above zero)"
                    ),
                ));
            }
            if m1 + m2 < m3 * (1.0 - INERTIA_SLACK) {
                return Err(field(
                    file,
                    place,
                    "inertia",
                    format!(
                        "principal moments {m1:e}, {m2:e}, {m3:e} kg m^2 violate the triangle \
                         inequality ({m1:e} + {m2:e} < {m3:e}): no mass distribution has them"
                    ),
                ));
            }
        }
        Ok(())
    }

    /// A leg with joints but no foot would silently drop out of every plan: say so.
    fn check_feet(&self, file: &str) -> Result<(), ModelError> {
        for leg in Leg::ALL {
            let joints: Vec<&str> = self
                .joints
                .iter()
                .filter(|j| j.leg == leg)
                .map(|j| j.name.as_str())
                .collect();
            if !joints.is_empty() && self.foot(leg).is_none() {
                return Err(field(
                    file,
                    format!("leg {}", leg.name()),
                    "foot",
                    format!(
                        "missing: the leg has joints ({}) but no foot (a `[[foot]]` entry in a \
                         model file, a `{}_Tip` body in an AnimatLab project)",
                        joints.join(", "),
                        leg.name()
                    ),
                ));
            }
        }
        Ok(())
    }
}

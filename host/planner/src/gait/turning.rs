//! Turning: a curve given as the thorax's turn per step and the radius of its path, turned into
//! stepping parameters ([`Turn::apply`]): the one rule behind `dbot plan --turn/--radius` and
//! Python's `dbot.plan(model, turn_deg=..., radius_m=...)`, so both refuse alike.
//!
//! The planner moves the thorax at a constant velocity v = translation_m / stance and yaw rate
//! w = rotation_rad / stance over the whole cycle (`planner::plan::plan`), so over one step cycle
//! of period T it turns by w T = rotation_rad / duty and travels on a circle about the
//! instantaneous centre (0, v / w) of the thorax frame (`GroundMotion::new`): the radius is
//! translation_m / rotation_rad, positive with the centre on the left.

use super::{ParamError, StepParams};

/// Largest |turn| per step cycle, deg: beyond half a revolution a step's turn is ambiguous (a
/// yaw of 190 deg left looks like 170 deg right), and no leg reaches that far.
pub const MAX_TURN_DEG: f64 = 180.0;

/// Largest |radius|, m: the limit the planner sets on every length (`StepParams::validate`);
/// a curve wider than that is straight walking for any robot.
pub const MAX_RADIUS_M: f64 = 100.0;

/// A curve to plan: the turn per step, the radius, or both (see [`Turn::apply`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Turn {
    /// The thorax's yaw per step cycle, deg; positive turns left.
    pub turn_deg: Option<f64>,
    /// Radius of the thorax's path, m: the turning centre's distance to the left of the thorax
    /// (negative: to the right); 0 (with `turn_deg`) turns on the spot.
    pub radius_m: Option<f64>,
}

impl Turn {
    /// Sets the rotation (and with both fields the translation) of `p` for this curve, after the
    /// rest of `p` (the duty cycle above all) is final:
    ///
    /// - `turn_deg` alone: rotation_rad = turn x duty (per stance); the translation stays, so the
    ///   radius is translation / rotation (straight with turn 0).
    /// - `radius_m` alone: rotation_rad = translation / radius; the stride stays. Refused for
    ///   radius 0 (on the spot needs the turn too) and for no translation.
    /// - both: rotation_rad = turn x duty and translation_m = radius x rotation_rad (a walk
    ///   forward for a left turn on a left centre; radius 0: on the spot). Refused for turn 0.
    ///
    /// Errors name the field (`turn_deg`, `radius_m`) and its range.
    pub fn apply(&self, p: &mut StepParams) -> Result<(), ParamError> {
        let bad = |field, value: f64, problem| ParamError::Invalid {
            field,
            value: value.to_string(),
            problem,
        };
        if let Some(t) = self.turn_deg
            && !(t.is_finite() && t.abs() < MAX_TURN_DEG)
        {
            return Err(bad(
                "turn_deg",
                t,
                "the turn per step must lie between -180 and 180 deg (exclusive; positive left)",
            ));
        }
        if let Some(r) = self.radius_m
            && !(r.is_finite() && r.abs() <= MAX_RADIUS_M)
        {
            return Err(bad(
                "radius_m",
                r,
                "the radius must lie between -100 and 100 m (positive: centre on the left)",
            ));
        }
        let per_stance = |deg: f64| deg.to_radians() * p.duty;
        match (self.turn_deg, self.radius_m) {
            (None, None) => {}
            (Some(t), None) => p.rotation_rad = per_stance(t),
            (None, Some(r)) => {
                if r == 0.0 {
                    return Err(bad(
                        "radius_m",
                        r,
                        "radius 0 turns on the spot: give the turn per step (turn_deg) too",
                    ));
                }
                if p.translation_m == 0.0 {
                    return Err(bad(
                        "radius_m",
                        r,
                        "the plan does not travel (translation_m 0): give the turn per step \
                         (turn_deg) too",
                    ));
                }
                let rotation = p.translation_m / r;
                let turn = rotation / p.duty;
                if turn.abs() >= MAX_TURN_DEG.to_radians() {
                    return Err(bad(
                        "radius_m",
                        r,
                        "so tight a radius turns by 180 deg or more per step at this stride: \
                         |radius| must exceed translation_m / (pi duty)",
                    ));
                }
                p.rotation_rad = rotation;
            }
            (Some(t), Some(r)) => {
                if t == 0.0 {
                    return Err(bad(
                        "turn_deg",
                        t,
                        "a radius needs a turn: give a non-zero turn per step with radius_m",
                    ));
                }
                p.rotation_rad = per_stance(t);
                p.translation_m = r * p.rotation_rad;
            }
        }
        Ok(())
    }
}

impl StepParams {
    /// The thorax's yaw per step cycle, rad (rotation per stance / duty); positive left.
    pub fn turn_per_step_rad(&self) -> f64 {
        self.rotation_rad / self.duty
    }

    /// Radius of the thorax's path, m, positive with the centre on the left; `None` when the plan
    /// does not turn.
    pub fn turn_radius_m(&self) -> Option<f64> {
        (self.rotation_rad != 0.0).then(|| self.translation_m / self.rotation_rad)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn base() -> StepParams {
        // servo-safe: translation 0.085 m per stance, duty 0.6.
        StepParams::preset("servo-safe", "drosophibot2").unwrap()
    }

    fn applied(turn_deg: Option<f64>, radius_m: Option<f64>) -> Result<StepParams, ParamError> {
        let mut p = base();
        Turn { turn_deg, radius_m }.apply(&mut p)?;
        Ok(p)
    }

    fn field(e: ParamError) -> &'static str {
        match e {
            ParamError::Invalid { field, .. } => field,
            ParamError::File { .. } => panic!("not a field error"),
        }
    }

    #[test]
    fn a_turn_per_step_sets_the_rotation_per_stance() {
        // 10 deg per 2.5 s cycle = 10 deg x 0.6 = 6 deg = 0.104720 rad per 1.5 s stance.
        let p = applied(Some(10.0), None).unwrap();
        assert!((p.rotation_rad - 0.104_719_755).abs() < 1e-9);
        assert_eq!(p.translation_m, 0.085);
        assert!((p.turn_per_step_rad().to_degrees() - 10.0).abs() < 1e-12);
        // Radius 0.085 m / 0.10472 rad = 0.8117 m, centre on the left.
        assert!((p.turn_radius_m().unwrap() - 0.811_690).abs() < 1e-6);
    }

    #[test]
    fn a_radius_keeps_the_stride_and_sets_the_turn() {
        // 0.085 m on a 0.5 m radius: 0.17 rad per stance, 0.2833 rad = 16.23 deg per step.
        let p = applied(None, Some(0.5)).unwrap();
        assert!((p.rotation_rad - 0.17).abs() < 1e-12);
        assert!((p.turn_per_step_rad() - 0.17 / 0.6).abs() < 1e-12);
        // Right: the centre on the right, the yaw clockwise.
        let p = applied(None, Some(-0.5)).unwrap();
        assert!((p.rotation_rad + 0.17).abs() < 1e-12);
        assert!((p.turn_radius_m().unwrap() + 0.5).abs() < 1e-12);
    }

    #[test]
    fn turn_and_radius_set_the_stride_and_zero_radius_turns_on_the_spot() {
        // 15 deg per step on 0.4 m: rotation 9 deg = 0.15708 rad, stride 0.4 x that = 0.062832 m.
        let p = applied(Some(15.0), Some(0.4)).unwrap();
        assert!((p.translation_m - 0.062_831_853).abs() < 1e-9);
        assert!((p.turn_radius_m().unwrap() - 0.4).abs() < 1e-12);
        let p = applied(Some(-20.0), Some(0.0)).unwrap();
        assert_eq!(p.translation_m, 0.0);
        assert!((p.turn_per_step_rad().to_degrees() + 20.0).abs() < 1e-12);
        assert_eq!(p.turn_radius_m(), Some(0.0));
        p.validate().unwrap();
    }

    #[test]
    fn nonsense_is_refused_naming_the_field() {
        for (t, r, f) in [
            (Some(180.0), None, "turn_deg"),
            (Some(f64::NAN), None, "turn_deg"),
            (None, Some(0.0), "radius_m"),
            (None, Some(f64::INFINITY), "radius_m"),
            (None, Some(-150.0), "radius_m"),
            (Some(0.0), Some(0.3), "turn_deg"),
            // 0.085 m on 0.02 m: 4.25 rad per stance, over half a turn per step.
            (None, Some(0.02), "radius_m"),
        ] {
            assert_eq!(field(applied(t, r).unwrap_err()), f, "{t:?} {r:?}");
        }
        let mut still = base();
        still.translation_m = 0.0;
        let e = Turn {
            turn_deg: None,
            radius_m: Some(0.5),
        }
        .apply(&mut still)
        .unwrap_err();
        assert!(e.to_string().contains("translation_m 0"), "{e}");
    }

    #[test]
    fn no_turn_leaves_the_parameters_alone() {
        assert_eq!(applied(None, None).unwrap(), base());
        assert_eq!(base().turn_radius_m(), None);
    }
}

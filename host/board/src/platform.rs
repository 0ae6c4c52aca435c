//! The perturbation platform as a trial sets it up: which leg stands on it, at which step it
//! moves and where to (`LEG:STEP:rise`, the spelling `dbot record --perturb` and Python's
//! `Board.set_platform` share), the platform servo's ID and goal positions (the lab's defaults,
//! `../shared/reference/lab-practice.md`), checked here before anything is sent or moves: a leg
//! that is not a leg, a step beyond the run's steps, and everything
//! [`protocol::PlatformSetup::check`] refuses. The board applies the same rule again, and checks
//! the servo answers ([`crate::link::Board::set_platform`]).

use planner::model::Leg;
use protocol::{PlatformError, PlatformMove, PlatformSetup, Steps};

use crate::trial::Perturbation;

/// The lab's platform servo ID (after its joints' IDs 0-21). The built-in model numbers its
/// joints' servos 1-22, so on its gaits the platform needs another ID: [`default_platform_id`].
pub const LAB_PLATFORM_ID: u8 = 22;

/// The platform servo's ID when none is given, for a gait whose joints' servos have
/// `servo_ids`: the lab's [`LAB_PLATFORM_ID`] unless a joint uses it, then the first ID after
/// the joints' highest that no joint uses (23 for the built-in model's 1-22). The one place
/// the CLI and Python choose it.
pub fn default_platform_id(servo_ids: &[u8]) -> u8 {
    if !servo_ids.contains(&LAB_PLATFORM_ID) {
        return LAB_PLATFORM_ID;
    }
    let after = servo_ids.iter().copied().max().unwrap_or(0);
    (after.saturating_add(1)..=protocol::platform::MAX_SERVO_ID)
        .find(|id| !servo_ids.contains(id))
        .unwrap_or(protocol::platform::MAX_SERVO_ID)
}

/// [`default_platform_id`] for the gait of step table `table` (its joints' servo IDs), or
/// without a table (or one that does not parse) for the built-in robot's servos (23).
pub fn default_platform_id_for(table: Option<&[u8]>) -> u8 {
    let ids: Vec<u8> = match table.and_then(|t| protocol::GaitTable::parse(t).ok()) {
        Some(t) => (0..t.joint_count())
            .filter_map(|j| t.joint(j).map(|m| m.servo_id))
            .collect(),
        None => crate::robot::robot_servos()
            .iter()
            .map(|(id, _)| *id)
            .collect(),
    };
    default_platform_id(&ids)
}

/// A perturbation of one trial: the leg on the platform and the platform's set-up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Perturb {
    pub leg: Leg,
    pub setup: PlatformSetup,
}

/// Why a perturbation cannot be set up.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum PerturbError {
    /// `LEG:STEP:MOVE` has not three parts.
    #[error("perturbation `{spec}` is not LEG:STEP:MOVE (e.g. RM:3:rise)")]
    Form { spec: String },
    /// The leg is not one of the six.
    #[error("perturbation leg `{leg}` is not a leg (legs: LF, LM, LH, RF, RM, RH)")]
    Leg { leg: String },
    /// The step is not a whole number.
    #[error("perturbation step `{step}` is not a whole number of steps (counted from 0)")]
    Step { step: String },
    /// The move is neither `rise` nor `fall`.
    #[error("perturbation move `{moves}` is neither rise nor fall")]
    Move { moves: String },
    /// The platform's rule (`protocol::platform`).
    #[error("perturbation platform: {0}")]
    Platform(PlatformError),
}

impl Perturb {
    /// The lab's platform (ID 22, rest 2020, rise 2330, fall 1570 ticks, back to rest two
    /// cycles later; profile velocity 240, an ESTIMATE) under `leg`, moving at `step`.
    pub fn lab(leg: Leg, step: u32, moves: PlatformMove) -> Self {
        Self {
            leg,
            setup: PlatformSetup::lab(moves, step),
        }
    }

    /// Parses `LEG:STEP:MOVE` (`RM:3:rise`, `LF:0:fall`) into the lab's platform on servo
    /// `servo_id`, checked against the platform's rule (no joint map yet: the board and
    /// [`crate::link::Board::set_platform`] check that).
    pub fn parse(spec: &str, servo_id: u8) -> Result<Self, PerturbError> {
        let parts: Vec<&str> = spec.split(':').collect();
        let [leg, step, moves] = parts[..] else {
            return Err(PerturbError::Form {
                spec: spec.to_owned(),
            });
        };
        let leg = leg_named(leg)?;
        let step = step.parse::<u32>().map_err(|_| PerturbError::Step {
            step: step.to_owned(),
        })?;
        let moves = match moves {
            "rise" => PlatformMove::Rise,
            "fall" => PlatformMove::Fall,
            _ => {
                return Err(PerturbError::Move {
                    moves: moves.to_owned(),
                });
            }
        };
        let mut p = Self::lab(leg, step, moves);
        p.setup.servo_id = servo_id;
        p.setup.check(&[]).map_err(PerturbError::Platform)?;
        Ok(p)
    }

    /// Checks the step against a run of `steps` (`None`: until stopped).
    pub fn check_steps(&self, steps: Option<u32>) -> Result<(), PerturbError> {
        self.setup
            .check_run(steps.map_or(Steps::Continuous, Steps::Count))
            .map_err(PerturbError::Platform)
    }

    /// The trial record's perturbation.
    pub fn record(&self) -> Perturbation {
        Perturbation {
            leg: self.leg.name().to_owned(),
            step: self.setup.step,
            rest: self.setup.rest,
            moved_to: self.setup.moved_to(),
            platform_id: Some(self.setup.servo_id),
        }
    }
}

/// The leg named `name` (`LF`, `LM`, `LH`, `RF`, `RM`, `RH`).
pub fn leg_named(name: &str) -> Result<Leg, PerturbError> {
    Leg::ALL
        .into_iter()
        .find(|l| l.name() == name)
        .ok_or_else(|| PerturbError::Leg {
            leg: name.to_owned(),
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_labs_rise_under_a_leg_reads_from_its_spec() {
        let p = Perturb::parse("RM:3:rise", 23).unwrap();
        assert_eq!(p.leg, Leg::RM);
        assert_eq!(
            (p.setup.servo_id, p.setup.step, p.setup.hold_cycles),
            (23, 3, 2)
        );
        assert_eq!(
            p.record(),
            Perturbation {
                leg: "RM".into(),
                step: 3,
                rest: 2020,
                moved_to: 2330,
                platform_id: Some(23),
            }
        );
        assert_eq!(
            Perturb::parse("LF:0:fall", 22).unwrap().record().moved_to,
            1570
        );
    }

    #[test]
    fn the_default_id_is_the_labs_unless_a_joint_has_it() {
        // The lab's joints 0-21: 22 is free.
        let lab: Vec<u8> = (0..=21).collect();
        assert_eq!(default_platform_id(&lab), 22);
        // The built-in model's 1-22: the first after them.
        let ours: Vec<u8> = (1..=22).collect();
        assert_eq!(default_platform_id(&ours), 23);
        // No joint map known: the lab's.
        assert_eq!(default_platform_id(&[]), 22);
    }

    #[test]
    fn bad_specs_are_named() {
        let e = |s: &str| Perturb::parse(s, 22).unwrap_err().to_string();
        assert_eq!(
            e("LX:3:rise"),
            "perturbation leg `LX` is not a leg (legs: LF, LM, LH, RF, RM, RH)"
        );
        assert_eq!(
            e("RM:three:rise"),
            "perturbation step `three` is not a whole number of steps (counted from 0)"
        );
        assert_eq!(
            e("RM:3:up"),
            "perturbation move `up` is neither rise nor fall"
        );
        assert_eq!(
            e("RM:3"),
            "perturbation `RM:3` is not LEG:STEP:MOVE (e.g. RM:3:rise)"
        );
        assert_eq!(
            Perturb::parse("RM:3:rise", 254).unwrap_err().to_string(),
            "perturbation platform: platform servo ID 254 is not a servo ID (0 ..= 252)"
        );
    }

    #[test]
    fn a_step_beyond_the_run_is_refused() {
        let p = Perturb::parse("RM:10:rise", 23).unwrap();
        assert_eq!(
            p.check_steps(Some(10)).unwrap_err().to_string(),
            "perturbation platform: perturbation step 10 is beyond the run's 10 steps (steps \
             count from 0, so the last is 9)"
        );
        assert!(p.check_steps(Some(11)).is_ok());
        assert!(p.check_steps(None).is_ok());
    }
}

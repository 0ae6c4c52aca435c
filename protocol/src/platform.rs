//! The perturbation platform's one rule, shared by the host (checks before it sends
//! `SetPlatform` or plays) and the firmware (refuses the same with the same [`PlatformError`]):
//! a servo ID that is no joint's and on the bus's range, goal positions within the servo's turn,
//! a hold of at least one cycle, and a perturbed step within the run.
//!
//! The schedule ([`PlatformSetup::goal`]): every bus cycle that writes goals carries the
//! platform's, `rest` until the first cycle of step `step`, then `rise` (or `fall`) for
//! `hold_cycles` cycles, then `rest` again (the lab's practice,
//! `../shared/reference/lab-practice.md`).

use core::fmt;

use crate::message::{PlatformMove, PlatformSetup, Steps};

/// Highest goal position, ticks (one turn is 4096).
pub const MAX_TICKS: u16 = 4095;
/// Highest Dynamixel ID a servo can have (253 is reserved, 254 is broadcast).
pub const MAX_SERVO_ID: u8 = 252;

/// Which of the platform's goal positions an error names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PlatformPosition {
    Rest,
    Rise,
    Fall,
}

impl PlatformPosition {
    pub const fn name(self) -> &'static str {
        match self {
            Self::Rest => "rest",
            Self::Rise => "rise",
            Self::Fall => "fall",
        }
    }
}

/// Why a platform cannot be set up or a run with it not started.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum PlatformError {
    /// The platform servo's ID is the ID of joint `joint` of the gait's joint map.
    JointId { servo_id: u8, joint: u8 },
    /// The ID is above [`MAX_SERVO_ID`].
    BadId { servo_id: u8 },
    /// A goal position outside 0 ..= [`MAX_TICKS`].
    Position {
        position: PlatformPosition,
        ticks: u16,
    },
    /// `hold_cycles` is 0: the platform would never move.
    ZeroHold,
    /// The perturbed step is not one of the run's `steps` steps (0 ..= steps - 1).
    StepBeyondRun { step: u32, steps: u32 },
    /// The platform servo did not answer at set-up (ping, profile velocity write or position
    /// read).
    NotAnswering { servo_id: u8 },
    /// The board has not checked the servo yet (it does at its next bus cycle): ask again.
    Checking { servo_id: u8 },
    /// The gait has `joints` joints: no room beside them in a Sync Write.
    NoRoom { joints: u8 },
}

impl fmt::Display for PlatformError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::JointId { servo_id, joint } => write!(
                f,
                "platform servo ID {servo_id} is the ID of joint {joint}: the platform needs a \
                 servo of its own"
            ),
            Self::BadId { servo_id } => write!(
                f,
                "platform servo ID {servo_id} is not a servo ID (0 ..= {MAX_SERVO_ID})"
            ),
            Self::Position { position, ticks } => write!(
                f,
                "platform {} position {ticks} ticks is outside 0 ..= {MAX_TICKS}",
                position.name()
            ),
            Self::ZeroHold => write!(f, "platform hold of 0 cycles: it would never move"),
            Self::StepBeyondRun { step, steps } => write!(
                f,
                "perturbation step {step} is beyond the run's {steps} steps (steps count from 0, \
                 so the last is {})",
                steps.saturating_sub(1)
            ),
            Self::NotAnswering { servo_id } => write!(
                f,
                "platform servo ID {servo_id} does not answer (ping, profile velocity or position \
                 read failed): check its cable and ID"
            ),
            Self::Checking { servo_id } => write!(
                f,
                "platform servo ID {servo_id} is being checked by the board: ask again"
            ),
            Self::NoRoom { joints } => write!(
                f,
                "the gait has {joints} joints: no room for the platform servo beside them"
            ),
        }
    }
}

impl core::error::Error for PlatformError {}

impl PlatformSetup {
    /// The lab's platform moving `moves` at `step`: ID 22, rest 2020, rise 2330, fall 1570 ticks,
    /// back to rest two cycles later. Profile velocity 240 (55 rev/min, about an MX-28's no-load
    /// speed) is an ESTIMATE: the lab sets it before each trial and does not publish it.
    pub const fn lab(moves: PlatformMove, step: u32) -> Self {
        Self {
            servo_id: 22,
            rest: 2020,
            rise: 2330,
            fall: 1570,
            profile_velocity: 240,
            moves,
            step,
            hold_cycles: 2,
        }
    }

    /// Checks the set-up against the joint map's servo IDs (`joint_ids[j]` = joint j's ID), in
    /// this order: the ID, the positions (rest, rise, fall), the hold.
    pub fn check(&self, joint_ids: &[u8]) -> Result<(), PlatformError> {
        if self.servo_id > MAX_SERVO_ID {
            return Err(PlatformError::BadId {
                servo_id: self.servo_id,
            });
        }
        if let Some(joint) = joint_ids.iter().position(|&id| id == self.servo_id) {
            return Err(PlatformError::JointId {
                servo_id: self.servo_id,
                joint: joint as u8,
            });
        }
        for (position, ticks) in [
            (PlatformPosition::Rest, self.rest),
            (PlatformPosition::Rise, self.rise),
            (PlatformPosition::Fall, self.fall),
        ] {
            if ticks > MAX_TICKS {
                return Err(PlatformError::Position { position, ticks });
            }
        }
        if self.hold_cycles == 0 {
            return Err(PlatformError::ZeroHold);
        }
        Ok(())
    }

    /// Checks the perturbed step against a run of `steps` (an endless run reaches every step).
    pub fn check_run(&self, steps: Steps) -> Result<(), PlatformError> {
        match steps {
            Steps::Count(n) if self.step >= n => Err(PlatformError::StepBeyondRun {
                step: self.step,
                steps: n,
            }),
            Steps::Count(_) | Steps::Continuous => Ok(()),
        }
    }

    /// The goal the platform moves to at the perturbed step.
    pub const fn moved_to(&self) -> u16 {
        match self.moves {
            PlatformMove::Rise => self.rise,
            PlatformMove::Fall => self.fall,
        }
    }

    /// The goal in the bus cycle `cycles_in_step` cycles (0: the first) into the step after
    /// `steps_done` whole steps of the run.
    pub const fn goal(&self, steps_done: u32, cycles_in_step: u32) -> u16 {
        if steps_done == self.step && cycles_in_step < self.hold_cycles as u32 {
            self.moved_to()
        } else {
            self.rest
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const JOINTS: [u8; 22] = [
        0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21,
    ];

    #[test]
    fn the_lab_platform_passes_and_nonsense_is_named() {
        let lab = PlatformSetup::lab(PlatformMove::Rise, 3);
        assert_eq!(lab.check(&JOINTS), Ok(()));
        let joint = PlatformSetup { servo_id: 7, ..lab };
        assert_eq!(
            joint.check(&JOINTS),
            Err(PlatformError::JointId {
                servo_id: 7,
                joint: 7
            })
        );
        let bad = PlatformSetup {
            servo_id: 254,
            ..lab
        };
        assert_eq!(
            bad.check(&JOINTS),
            Err(PlatformError::BadId { servo_id: 254 })
        );
        let far = PlatformSetup { rise: 4096, ..lab };
        assert_eq!(
            far.check(&JOINTS),
            Err(PlatformError::Position {
                position: PlatformPosition::Rise,
                ticks: 4096
            })
        );
        let never = PlatformSetup {
            hold_cycles: 0,
            ..lab
        };
        assert_eq!(never.check(&JOINTS), Err(PlatformError::ZeroHold));
    }

    #[test]
    fn the_step_must_be_one_of_the_run() {
        let p = PlatformSetup::lab(PlatformMove::Rise, 3);
        // Four steps are 0, 1, 2, 3: step 3 is the last.
        assert_eq!(p.check_run(Steps::Count(4)), Ok(()));
        assert_eq!(
            p.check_run(Steps::Count(3)),
            Err(PlatformError::StepBeyondRun { step: 3, steps: 3 })
        );
        assert_eq!(p.check_run(Steps::Continuous), Ok(()));
    }

    #[test]
    fn the_lab_schedule_rises_for_two_cycles_then_rests() {
        let p = PlatformSetup::lab(PlatformMove::Rise, 2);
        assert_eq!(p.goal(1, 40), 2020);
        assert_eq!(p.goal(2, 0), 2330);
        assert_eq!(p.goal(2, 1), 2330);
        assert_eq!(p.goal(2, 2), 2020);
        assert_eq!(p.goal(3, 0), 2020);
        let fall = PlatformSetup {
            moves: PlatformMove::Fall,
            ..p
        };
        assert_eq!(fall.goal(2, 1), 1570);
    }
}

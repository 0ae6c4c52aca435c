//! The perturbation platform on the board: an auxiliary servo beside the joints whose goal rides in
//! the joints' own Sync Write every bus cycle that writes goals, `rest` until the first cycle of
//! the chosen step, then `rise` (or `fall`) for `hold_cycles` cycles, then `rest`
//! ([`protocol::PlatformSetup::goal`], the one schedule). Set up with `set_platform` when not
//! moving; the next bus action checks the servo ([`BusAction::PlatformCheck`]: ping, profile
//! velocity, goal `rest`, position read), and `play` refuses a servo that did not answer and a
//! step beyond the run.

use dynamixel::master::{BusError, Goal, Reply, ReplyFault};
use embedded_storage::nor_flash::NorFlash;
use protocol::{PlatformError, PlatformSetup, PlatformState, PlatformStatus, Steps};

use super::{BusAction, CommandError, Controller, CyclePlan};
use crate::playback::MAX_JOINTS;
use crate::safety::State;
use crate::store::FlashWindow;
use crate::telemetry::{PlatformSample, flags};

/// The platform set up, its servo's state and where its schedule is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct PlatformRun {
    pub setup: PlatformSetup,
    pub state: PlatformState,
    /// The goal the last goal-writing cycle carried, ticks.
    pub goal: u16,
    /// Last good present position, ticks, and the flags of the last reply.
    pub present: u16,
    pub flags: u8,
    /// The step the schedule saw last and the goal-writing cycles into it.
    step_seen: Option<u32>,
    cycles_in_step: u32,
}

/// What the platform check reads back: the present position, ticks.
pub type CheckResult = Result<u16, BusError>;

impl<F: NorFlash + FlashWindow> Controller<F> {
    /// Sets up the platform for the next runs (not while moving), checked against the joint map;
    /// the board checks the servo at its next bus cycle.
    pub fn set_platform(&mut self, setup: PlatformSetup) -> Result<(), CommandError> {
        self.platform_not_moving()?;
        self.check_platform_ids(&setup)?;
        self.platform = Some(PlatformRun {
            setup,
            state: PlatformState::Checking,
            goal: setup.rest,
            present: 0,
            flags: flags::NO_REPLY,
            step_seen: None,
            cycles_in_step: 0,
        });
        Ok(())
    }

    /// No platform any more (not while moving); its servo keeps its last goal.
    pub fn clear_platform(&mut self) -> Result<(), CommandError> {
        self.platform_not_moving()?;
        self.platform = None;
        Ok(())
    }

    /// The platform set up and its servo's state.
    pub fn platform(&self) -> Option<PlatformStatus> {
        self.platform.map(|p| PlatformStatus {
            setup: p.setup,
            state: p.state,
        })
    }

    fn platform_not_moving(&self) -> Result<(), CommandError> {
        if matches!(self.state, State::Boot | State::Idle | State::Standing) {
            Ok(())
        } else {
            Err(CommandError::Moving { state: self.state })
        }
    }

    fn check_platform_ids(&self, setup: &PlatformSetup) -> Result<(), CommandError> {
        let mut ids = [0u8; MAX_JOINTS];
        for (i, j) in ids.iter_mut().zip(&self.joints) {
            *i = j.id;
        }
        setup
            .check(&ids[..self.joints.len()])
            .map_err(CommandError::Platform)?;
        if self.joints.len() >= MAX_JOINTS {
            return Err(CommandError::Platform(PlatformError::NoRoom {
                joints: self.joints.len() as u8,
            }));
        }
        Ok(())
    }

    /// `play`'s check, after the gait is selected: the platform (if any) answered, its ID is
    /// still no joint's, and its step is one of the run's.
    pub(crate) fn platform_ready_for(&mut self, steps: Option<u32>) -> Result<(), CommandError> {
        let Some(p) = self.platform else {
            return Ok(());
        };
        let servo_id = p.setup.servo_id;
        match p.state {
            PlatformState::Checking => {
                return Err(CommandError::Platform(PlatformError::Checking { servo_id }));
            }
            PlatformState::NotAnswering => {
                return Err(CommandError::Platform(PlatformError::NotAnswering {
                    servo_id,
                }));
            }
            PlatformState::Ready { .. } => {}
        }
        self.check_platform_ids(&p.setup)?;
        let steps = steps.map_or(Steps::Continuous, Steps::Count);
        p.setup.check_run(steps).map_err(CommandError::Platform)?;
        if let Some(run) = self.platform.as_mut() {
            run.step_seen = None;
            run.cycles_in_step = 0;
        }
        Ok(())
    }

    /// The platform check is due (set up, not checked yet).
    pub(crate) fn platform_check_due(&self) -> Option<BusAction> {
        let p = self.platform?;
        (p.state == PlatformState::Checking).then_some(BusAction::PlatformCheck {
            id: p.setup.servo_id,
            profile_velocity: p.setup.profile_velocity,
            rest: p.setup.rest,
            torque: self.torque_sent,
        })
    }

    /// The platform's goal for a cycle that plans `action` (after the joints' goals and the
    /// playback clock moved): `None` without a ready platform. Advances the schedule on cycles
    /// that write goals while walking.
    pub(crate) fn platform_goal(&mut self, action: BusAction) -> Option<Goal> {
        let walking = matches!(self.state, State::Walking | State::Stopping);
        let step = self.playback().map(|(step, _)| step);
        let p = self.platform.as_mut()?;
        if !matches!(p.state, PlatformState::Ready { .. }) {
            return None;
        }
        let writes = matches!(
            action,
            BusAction::Cycle | BusAction::WriteGains | BusAction::TorqueOn
        );
        if writes {
            p.goal = match (walking, step) {
                (true, Some(step)) => {
                    if p.step_seen == Some(step) {
                        p.cycles_in_step = p.cycles_in_step.saturating_add(1);
                    } else {
                        p.step_seen = Some(step);
                        p.cycles_in_step = 0;
                    }
                    p.setup.goal(step, p.cycles_in_step)
                }
                _ => {
                    p.step_seen = None;
                    p.setup.rest
                }
            };
        }
        Some(Goal {
            id: p.setup.servo_id,
            position: i32::from(p.goal),
        })
    }

    /// What the platform check gave.
    pub(crate) fn platform_checked(&mut self, id: u8, result: CheckResult) {
        let Some(p) = self.platform.as_mut() else {
            return;
        };
        if p.setup.servo_id != id {
            // Set up anew while the check was on the bus: the new one is checked next.
            return;
        }
        p.state = match result {
            Ok(present) => {
                p.present = present;
                p.flags = 0;
                PlatformState::Ready { present }
            }
            Err(_) => PlatformState::NotAnswering,
        };
    }

    /// The platform servo's reply in a cycle's Sync Read.
    pub(crate) fn platform_reply(&mut self, reply: &Reply) {
        let Some(p) = self.platform.as_mut() else {
            return;
        };
        p.flags = match reply {
            Ok(fb) => {
                p.present = fb.position.clamp(0, i32::from(u16::MAX)) as u16;
                0
            }
            Err(ReplyFault::Status(_)) => 0,
            Err(ReplyFault::Crc | ReplyFault::Malformed) => flags::NO_REPLY | flags::CRC_ERROR,
            Err(_) => flags::NO_REPLY,
        };
    }

    /// The platform's line in the record of `plan`'s cycle.
    pub(crate) fn platform_sample(&self, plan: &CyclePlan) -> Option<PlatformSample> {
        let p = self.platform?;
        let goal = plan.platform?;
        Some(PlatformSample {
            id: goal.id,
            goal: goal.position.clamp(0, i32::from(u16::MAX)) as u16,
            present: p.present,
            flags: p.flags,
        })
    }
}

//! Host commands: what the link handler may ask of the controller, each checked against the state.

use embedded_storage::nor_flash::NorFlash;

use super::{Controller, Selected};
use crate::bias::JointCal;
use crate::gait_view::{self, stored_crc};
use crate::playback::{Direction, MAX_JOINTS, PlayClock};
use crate::safety::{Event, Refused, SafeReason, State};
use crate::store::{CommitError, FlashWindow, SlotInfo, StoreError};

/// Why a command was refused. Nothing changes when a command is refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum CommandError {
    /// The state machine does not take this command now.
    WrongState(Refused),
    /// Flash writes are refused while the robot moves (a sector erase stalls the bus loop).
    Moving { state: State },
    /// The slot is empty.
    SlotEmpty { slot: u8 },
    /// The slot's table does not validate.
    BadTable {
        slot: u8,
        error: protocol::TableError,
    },
    /// The slot is past the last one.
    NoSuchSlot { slot: u8, slots: u8 },
    /// The joint index is past the joint map.
    NoSuchJoint { joint: u8, joints: u8 },
    /// A setting is out of its range.
    OutOfRange { what: Setting, value: i64 },
    /// The gait store refused.
    Store(StoreError),
    /// A queued gait cannot follow the one before it (`protocol::switch`).
    Switch(protocol::SwitchError),
    /// A steering family or command was refused (`protocol::steer`).
    Steer(protocol::SteerError),
    /// The perturbation platform was refused (`protocol::platform`).
    Platform(protocol::PlatformError),
}

/// Which setting was out of range: the protocol's own names.
pub use protocol::Setting;

impl From<StoreError> for CommandError {
    fn from(e: StoreError) -> Self {
        match e {
            StoreError::NoSuchSlot { slot, slots } => CommandError::NoSuchSlot { slot, slots },
            e => CommandError::Store(e),
        }
    }
}

/// How to play a gait.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PlayParams {
    pub slot: u8,
    pub direction: Direction,
    /// Step period scale, 1/1000 (2000 = half speed).
    pub period_scale: u16,
    /// Whole steps to play, `None` until stopped.
    pub steps: Option<u32>,
}

/// The period scale (100 ..= 10 000) and step count (not 0) of a play or queue command.
pub(crate) fn check_play_params(p: &PlayParams) -> Result<(), CommandError> {
    if !(100..=10_000).contains(&p.period_scale) {
        return Err(CommandError::OutOfRange {
            what: Setting::PeriodScale,
            value: p.period_scale.into(),
        });
    }
    if p.steps == Some(0) {
        return Err(CommandError::OutOfRange {
            what: Setting::StepCount,
            value: 0,
        });
    }
    Ok(())
}

impl<F: NorFlash + FlashWindow> Controller<F> {
    pub(crate) fn apply(&mut self, event: Event) -> Result<(), CommandError> {
        let state = self.state;
        if self.event(event) {
            Ok(())
        } else {
            Err(CommandError::WrongState(Refused { state, event }))
        }
    }

    fn not_moving(&self) -> Result<(), CommandError> {
        if self.state.allows_flash_writes() {
            Ok(())
        } else {
            Err(CommandError::Moving { state: self.state })
        }
    }

    /// Validates the table of `slot` and takes its joint map, stiffness and limits. A map with other
    /// servo IDs than the one in use makes the controller look for the servos again (Boot), so it is
    /// only allowed while torque is off. Selecting the table already selected keeps the run-time
    /// settings (stiffness, limits) the host made since.
    pub(crate) fn select(&mut self, slot: u8) -> Result<(), CommandError> {
        let slots = self.store.slots();
        if slot >= slots {
            return Err(CommandError::NoSuchSlot { slot, slots });
        }
        let bytes = self
            .store
            .table(slot)
            .ok_or(CommandError::SlotEmpty { slot })?;
        // The table's own CRC tells a new upload apart, not the store's CRC-32 over the whole
        // table: with the table's CRC in its last bytes, that one is the same constant (the
        // CRC-32 residue) for every valid table.
        let crc = stored_crc(bytes);
        if self
            .selected
            .is_some_and(|s| s.slot == slot && s.crc == crc)
        {
            return Ok(());
        }
        let checked =
            gait_view::check(bytes).map_err(|error| CommandError::BadTable { slot, error })?;
        self.adopt(slot, checked, crc)
    }

    /// Takes over a checked table of `slot` (its CRC `crc`): joint map, stiffness, limits.
    pub(crate) fn adopt(
        &mut self,
        slot: u8,
        checked: gait_view::Checked,
        crc: u32,
    ) -> Result<(), CommandError> {
        let layout = checked.layout;
        let maps = checked.joints;
        let same_servos = maps.len() == self.joints.len()
            && maps.iter().zip(&self.joints).all(|(m, j)| m.id == j.id);
        if !same_servos && self.torque_sent {
            return Err(CommandError::WrongState(Refused {
                state: self.state,
                event: Event::Start,
            }));
        }
        self.stiffness = checked.stiffness;
        self.gains_wanted = self.gains_wanted.wrapping_add(1);
        self.joints = maps;
        self.selected = Some(Selected { slot, layout, crc });
        if !same_servos {
            self.health.reset();
            self.known = [false; MAX_JOINTS];
            self.misses.reset();
            if self.state == State::Idle {
                self.state = State::Boot;
                crate::device_log::transition(
                    State::Idle,
                    State::Boot,
                    crate::device_log::Cause::NewJointMap,
                );
            }
        }
        Ok(())
    }

    /// Plays a gait: ramps from the present posture to its first slice, then walks.
    pub fn play(&mut self, p: PlayParams) -> Result<(), CommandError> {
        if !matches!(self.state, State::Idle | State::Standing) {
            return Err(CommandError::WrongState(Refused {
                state: self.state,
                event: Event::Start,
            }));
        }
        check_play_params(&p)?;
        self.select(p.slot)?;
        let Some(sel) = self.selected else {
            return Err(CommandError::SlotEmpty { slot: p.slot });
        };
        if self.state == State::Boot {
            // New servos: Boot finds them; the host plays again once the board is Idle.
            return Err(CommandError::WrongState(Refused {
                state: State::Boot,
                event: Event::Start,
            }));
        }
        self.platform_ready_for(p.steps)?;
        let mut clock = PlayClock::new(sel.layout.period_us, p.direction, p.steps);
        clock.set_scale(p.period_scale.into());
        self.play = Some(clock);
        self.steps_before = 0;
        self.host_quiet = 0;
        self.health_stop = None;
        self.apply(Event::Start)
    }

    /// The host was heard from (any frame): restarts the host-loss count of an endless run.
    pub fn host_contact(&mut self) {
        self.host_quiet = 0;
    }

    /// Stops at the end of the current step.
    pub fn stop(&mut self) -> Result<(), CommandError> {
        self.apply(Event::Stop)
    }

    /// Torque off on every servo, from any state.
    pub fn emergency_stop(&mut self) {
        self.event(Event::EStop);
    }

    /// Leaves Safe or EStop for Idle (torque off).
    pub fn clear_fault(&mut self) -> Result<(), CommandError> {
        self.apply(Event::ClearFault)
    }

    /// Reboots all servos (`joint` None) or the servo of one joint (clears its latched hardware
    /// error), then looks for all of them again (Boot, then Idle with torque off).
    pub fn reboot_servos(&mut self, joint: Option<u8>) -> Result<(), CommandError> {
        if let Some(j) = joint {
            self.check_joint(j)?;
        }
        self.apply(Event::Reboot)?;
        self.reboot_pending = Some(joint.map_or(u32::MAX, |j| 1 << j));
        Ok(())
    }

    /// Torque on (hold the present posture) or off.
    pub fn set_torque(&mut self, on: bool) -> Result<(), CommandError> {
        self.apply(if on {
            Event::TorqueOn
        } else {
            Event::TorqueOff
        })
    }

    /// The board came up from a watchdog reset: it stays safe until the host clears the fault.
    pub fn watchdog_reset(&mut self) {
        self.event(Event::Fault(SafeReason::Watchdog));
    }

    /// Period scale of the playing gait, 1/1000.
    pub fn set_period_scale(&mut self, scale: u16) -> Result<(), CommandError> {
        if !(100..=10_000).contains(&scale) {
            return Err(CommandError::OutOfRange {
                what: Setting::PeriodScale,
                value: scale.into(),
            });
        }
        if let Some(p) = self.play.as_mut() {
            p.set_scale(scale.into());
        }
        self.steer_scale(scale);
        Ok(())
    }

    /// Stiffness of `joint`, mN m/rad; takes effect from the next cycle, also while walking, where
    /// the goals do not step: the goal difference the new bias makes is taken up at most the
    /// servo's step per cycle ([`crate::goal_step`], `cycle::follow_stiffness`). It is
    /// the torque bias's divisor and, with torque on, the servo's Position P Gain
    /// (`dynamixel::units::p_gain_for_stiffness`, written once by the next bus cycle's
    /// `BusAction::WriteGains`, and at every torque-on). 0 switches the bias off and leaves the
    /// servo's P gain as it is (a gain of 0 would make it limp).
    pub fn set_stiffness(&mut self, joint: u8, stiffness: u32) -> Result<(), CommandError> {
        self.check_joint(joint)?;
        // 0 switches the bias off. Else the joint's servo must hold it in its P gain register
        // (`protocol::limits::p_gain_holds`, the host's rule too): a stiffness the gain clamps
        // would make the bias divide by a spring the servo is not.
        let model = self.joints[joint as usize].model;
        if stiffness != 0 && !protocol::limits::p_gain_holds(model, stiffness) {
            return Err(CommandError::OutOfRange {
                what: Setting::Stiffness,
                value: stiffness.into(),
            });
        }
        if self.stiffness[joint as usize] != stiffness {
            self.stiffness[joint as usize] = stiffness;
            self.gains_wanted = self.gains_wanted.wrapping_add(1);
        }
        Ok(())
    }

    /// Limits of `joint` in ticks.
    pub fn set_limits(
        &mut self,
        joint: u8,
        min_ticks: i32,
        max_ticks: i32,
    ) -> Result<(), CommandError> {
        self.check_joint(joint)?;
        if !(0..=4095).contains(&min_ticks) || !(min_ticks..=4095).contains(&max_ticks) {
            return Err(CommandError::OutOfRange {
                what: Setting::Limits,
                value: min_ticks.into(),
            });
        }
        let j = &mut self.joints[joint as usize];
        *j = JointCal {
            min_ticks,
            max_ticks,
            ..*j
        };
        Ok(())
    }

    /// Bus cycle rate (Hz) and baud; only while nothing moves. Checked against
    /// `protocol::limits` (an MX baud, a rate whose cycles fit the wire for the robot's servos or
    /// the joint map's, whichever is larger), the same rule the host's flags and setup file use.
    pub fn set_bus(&mut self, baud: u32, cycle_hz: u16) -> Result<(), CommandError> {
        use protocol::limits::{LimitError, ROBOT_SERVOS, check_bus};
        self.not_moving()?;
        let servos = self.joints.len().max(ROBOT_SERVOS);
        check_bus(baud, cycle_hz, servos).map_err(|e| match e {
            LimitError::Baud { .. } => CommandError::OutOfRange {
                what: Setting::Baud,
                value: baud.into(),
            },
            LimitError::CycleRate { .. }
            | LimitError::Wire { .. }
            | LimitError::Stiffness { .. } => CommandError::OutOfRange {
                what: Setting::CycleRate,
                value: cycle_hz.into(),
            },
        })?;
        self.config.cycle_hz = cycle_hz;
        self.config.baud = baud;
        Ok(())
    }

    /// A telemetry record every `every` cycles (0 = off).
    pub fn set_telemetry(&mut self, every: u16) {
        self.config.telemetry_every = every;
        self.telemetry_countdown = 0;
    }

    /// Follows streamed setpoints; no setpoint for `timeout_cycles` cycles is a fault.
    pub fn enter_streaming(
        &mut self,
        timeout_cycles: u16,
        feedback_every: u16,
    ) -> Result<(), CommandError> {
        if timeout_cycles == 0 {
            return Err(CommandError::OutOfRange {
                what: Setting::StreamTimeout,
                value: 0,
            });
        }
        self.apply(Event::EnterStreaming)?;
        self.stream.timeout_cycles = timeout_cycles;
        self.stream.feedback_every = feedback_every.max(1);
        self.stream.age = 0;
        self.stream.countdown = 0;
        // No setpoint of this session yet: a number from an earlier one would name a setpoint
        // these cycles do not carry.
        self.stream.seq = 0;
        // Until a setpoint comes, the goals stay where they are.
        self.stream.target = self.goals;
        self.stream.planned_target = self.planned;
        Ok(())
    }

    pub fn leave_streaming(&mut self) -> Result<(), CommandError> {
        self.apply(Event::LeaveStreaming)
    }

    /// A streamed setpoint: per joint the angle (microradians) and optionally a torque (mN m) for the
    /// bias. Refused outside streaming. The goals move toward it from the next cycle by at most
    /// what the servo moves in one cycle ([`crate::goal_step::max_step_ticks`]: e.g. 37 ticks on
    /// an MX-28 at 100 Hz); a setpoint further away is approached at that rate, never jumped to
    /// (`Counters::rate_limited` counts the cut moves).
    pub fn setpoint(
        &mut self,
        seq: u32,
        joints: &[(i32, Option<i32>)],
    ) -> Result<(), CommandError> {
        if self.state != State::Streaming {
            return Err(CommandError::WrongState(Refused {
                state: self.state,
                event: Event::EnterStreaming,
            }));
        }
        if joints.len() != self.joints.len() {
            return Err(CommandError::OutOfRange {
                what: Setting::SetpointJoints,
                value: joints.len() as i64,
            });
        }
        for (j, &(angle, torque)) in joints.iter().enumerate() {
            let (g, c) = crate::bias::goal_ticks(
                &self.joints[j],
                angle,
                torque.unwrap_or(0),
                self.stiffness[j],
            );
            self.stream.target[j] = g;
            self.clamped[j] = c;
            self.stream.planned_target[j] = crate::bias::goal_ticks(&self.joints[j], angle, 0, 0).0;
        }
        self.stream.seq = seq;
        self.stream.age = 0;
        Ok(())
    }

    /// Sequence number and age (cycles) of the last setpoint.
    pub fn stream_status(&self) -> (u32, u16) {
        (self.stream.seq, self.stream.age)
    }

    fn check_joint(&self, joint: u8) -> Result<(), CommandError> {
        if (joint as usize) < self.joints.len() {
            Ok(())
        } else {
            Err(CommandError::NoSuchJoint {
                joint,
                joints: self.joints.len() as u8,
            })
        }
    }

    /// Starts an upload into `slot`; refused while moving and for the slot being played.
    pub fn upload_begin(&mut self, slot: u8, total_len: u32) -> Result<(), CommandError> {
        self.not_moving()?;
        self.flash_ops = self.flash_ops.wrapping_add(1);
        Ok(self.store.begin(slot, total_len)?)
    }

    pub fn upload_chunk(&mut self, offset: u32, data: &[u8]) -> Result<(), CommandError> {
        self.not_moving()?;
        self.flash_ops = self.flash_ops.wrapping_add(1);
        Ok(self.store.write(offset, data)?)
    }

    /// Commits the upload once its CRC-32 verifies; the slot's old table is replaced only then.
    pub fn upload_commit(&mut self, crc: u32) -> Result<SlotInfo, CommandError> {
        self.upload_commit_verified(crc, crate::store::accept_any)
            .map_err(|e| e.into_store().into())
    }

    /// As [`Controller::upload_commit`], with `verify` checking the table bytes in flash first.
    pub fn upload_commit_verified<E>(
        &mut self,
        crc: u32,
        verify: impl FnOnce(&[u8]) -> Result<(), E>,
    ) -> Result<SlotInfo, CommitError<E>> {
        if !self.state.allows_flash_writes() {
            // Only reachable if the caller skipped its own state check; nothing was written.
            self.store.abort();
            return Err(CommitError::Store(StoreError::NoUpload));
        }
        self.flash_ops = self.flash_ops.wrapping_add(1);
        let info = self.store.commit_verified(crc, verify)?;
        if self.selected.is_some_and(|s| s.slot == info.slot) || self.selected.is_none() {
            // The selected table changed under us: take the new one (or its error) now.
            let _ = self.select(info.slot);
        }
        Ok(info)
    }

    pub fn upload_abort(&mut self) {
        self.store.abort();
    }

    /// Empties a slot; refused while moving.
    pub fn delete_gait(&mut self, slot: u8) -> Result<(), CommandError> {
        self.not_moving()?;
        self.flash_ops = self.flash_ops.wrapping_add(1);
        self.store.delete(slot)?;
        if self.selected.is_some_and(|s| s.slot == slot) {
            self.selected = None;
            self.play = None;
        }
        Ok(())
    }
}

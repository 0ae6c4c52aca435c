//! Gait switching: the queue of gaits to play next and the step boundary at which the head of the
//! queue takes over. Whether a gait may follow another is `protocol::switch::check_switch`, asked
//! when the gait is queued (so a refusal comes back at once, with its reason, and the bus loop
//! never meets an incompatible table); the table is checked then too, so the switch itself in the
//! bus cycle costs no CRC.
//!
//! When the switch happens: an endless gait (`Steps::Continuous`) yields at its next step
//! boundary, a counted one once it has played its steps; a queue command that arrives mid-swing so
//! always waits for a boundary. The queued gait starts at its own slice 0, its clock at 0, its
//! torque bias and stiffness from its own table from the first cycle.

use embedded_storage::nor_flash::NorFlash;
use protocol::SwitchError;
use protocol::gait::GaitTable;

use super::{CommandError, Controller, PlayParams};
use crate::gait_view::{self, Checked};
use crate::playback::PlayClock;
use crate::safety::{Event, Refused, State};
use crate::store::FlashWindow;

/// Most gaits the board holds queued.
pub const QUEUE_LEN: usize = 4;

/// A queued gait: how to play it and its table, checked when it was queued.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Queued {
    pub params: PlayParams,
    pub checked: Checked,
    pub crc: u32,
}

impl<F: NorFlash + FlashWindow> Controller<F> {
    /// Queues a gait to follow the one playing (or the last one queued), refused with the
    /// protocol's [`SwitchError`] if it cannot follow it at a step boundary.
    pub fn queue_gait(&mut self, p: PlayParams) -> Result<(), CommandError> {
        if !matches!(self.state, State::Ramping | State::Walking) {
            return Err(CommandError::WrongState(Refused {
                state: self.state,
                event: Event::Queue,
            }));
        }
        super::commands::check_play_params(&p)?;
        if self.steer.is_some() {
            // The boundary goal of a blend is not the straight gait's slice 0 the rule checks.
            return Err(CommandError::Steer(protocol::SteerError::Steering));
        }
        if self.queue.is_full() {
            return Err(CommandError::Switch(SwitchError::QueueFull {
                capacity: QUEUE_LEN as u8,
            }));
        }
        let slots = self.store.slots();
        if p.slot >= slots {
            return Err(CommandError::NoSuchSlot {
                slot: p.slot,
                slots,
            });
        }
        let before = match self.queue.back() {
            Some(q) => q.params.slot,
            None => self
                .selected
                .map(|s| s.slot)
                .ok_or(CommandError::Switch(SwitchError::NothingPlaying))?,
        };
        let slot = p.slot;
        let bytes = self
            .store
            .table(slot)
            .ok_or(CommandError::SlotEmpty { slot })?;
        let queued =
            GaitTable::parse(bytes).map_err(|error| CommandError::BadTable { slot, error })?;
        let playing = self
            .store
            .table(before)
            .and_then(|b| GaitTable::parse(b).ok())
            .ok_or(CommandError::SlotEmpty { slot: before })?;
        protocol::check_switch(&playing, &queued, self.config.cycle_hz)
            .map_err(CommandError::Switch)?;
        let checked =
            gait_view::check(bytes).map_err(|error| CommandError::BadTable { slot, error })?;
        let crc = queued.crc();
        self.apply(Event::Queue)?;
        // Cannot fail: fullness was checked above and nothing between pops.
        let _ = self.queue.push_back(Queued {
            params: p,
            checked,
            crc,
        });
        Ok(())
    }

    /// Drops every queued gait; the one playing plays on.
    pub fn clear_queue(&mut self) -> Result<(), CommandError> {
        self.apply(Event::ClearQueue)?;
        self.queue.clear();
        Ok(())
    }

    /// Gaits waiting (slot numbers, in order).
    pub fn queued_slots(&self) -> impl Iterator<Item = u8> + '_ {
        self.queue.iter().map(|q| q.params.slot)
    }

    /// Whether an endless gait is queued (the host-loss rule covers it like an endless run).
    pub(crate) fn queue_endless(&self) -> bool {
        self.queue.iter().any(|q| q.params.steps.is_none())
    }

    /// At a step boundary of the gait playing: the queued gait takes over, if there is one and
    /// the state is Walking. True if it did.
    pub(crate) fn switch_at_boundary(&mut self) -> bool {
        if self.state != State::Walking {
            return false;
        }
        let Some(q) = self.queue.pop_front() else {
            return false;
        };
        let done = self.play.as_ref().map_or(0, |p| p.steps_done());
        // Same servos (checked when queued), so adopting never asks for Boot.
        if self.adopt(q.params.slot, q.checked, q.crc).is_err() {
            self.queue.clear();
            return false;
        }
        let Some(sel) = self.selected else {
            return false;
        };
        self.steps_before = self.steps_before.saturating_add(done);
        let mut clock = PlayClock::new(sel.layout.period_us, q.params.direction, q.params.steps);
        clock.set_scale(q.params.period_scale.into());
        self.play = Some(clock);
        self.event(Event::Switch)
    }
}

//! Steering: the descending command on the controller. A family of three gaits (straight, left,
//! right: `protocol::steer`'s rule, checked when the family is set and again when a steered walk
//! starts) is played as one: each cycle's goals are the straight table's and one side table's at the
//! same clock sample, blended by the signed weight of the commanded heading ([`Blend`]).
//!
//! When a command takes effect: from standing at once (the start ramp goes to the blend's first
//! slice); while walking at the next step boundary, where the weight moves towards the commanded
//! one by at most one side gait (`protocol::steer::blend_step`) and the period scale follows the
//! commanded speed. So no joint's goal moves across a boundary by more than the switch rule's bound,
//! a command mid-swing waits for the boundary, and a steered walk is an endless run that the
//! host-loss rule stops at the end of its step like any other.

use embedded_storage::nor_flash::NorFlash;
use protocol::gait::GaitTable;
use protocol::steer::{
    Side, SteerError, blend_of, blend_step, check_side, period_scale_of, side_of,
};
use protocol::{SteerCommand, SteerFamily};

use super::{CommandError, Controller, PlayParams};
use crate::gait_view::{self, Layout, View};
use crate::playback::{self, Direction, Gait, Sample};
use crate::safety::{Event, Refused, State};
use crate::store::FlashWindow;

/// A steered walk: the family, the side tables' layouts (the straight one is the selected gait),
/// the blend playing and the one commanded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Steering {
    family: SteerFamily,
    left: Layout,
    right: Layout,
    /// Signed weight playing, `protocol::steer::WEIGHT_ONE` = the left gait fully.
    blend: i32,
    /// Signed weight commanded.
    target: i32,
    /// Period scale commanded, 1e-3.
    scale: u16,
}

/// Two tables of one family at the same sample: `a` plus `w`/65536 of the way to `b`.
struct Blend<'a> {
    a: View<'a>,
    b: View<'a>,
    w: u32,
}

impl Gait for Blend<'_> {
    fn joints(&self) -> usize {
        self.a.joints()
    }
    fn slices(&self) -> usize {
        self.a.slices()
    }
    fn period_us(&self) -> u32 {
        self.a.period_us()
    }
    fn angle_urad(&self, slice: usize, joint: usize) -> i32 {
        let (a, b) = (
            self.a.angle_urad(slice, joint),
            self.b.angle_urad(slice, joint),
        );
        playback::lerp(a, b, self.w)
    }
    fn torque_mnm(&self, slice: usize, joint: usize) -> i32 {
        let (a, b) = (
            self.a.torque_mnm(slice, joint),
            self.b.torque_mnm(slice, joint),
        );
        playback::lerp(a, b, self.w)
    }
}

impl<F: NorFlash + FlashWindow> Controller<F> {
    /// Sets the family `Steer` blends, refused with the protocol's [`SteerError`] if its gaits
    /// cannot be blended, and while a steered walk plays.
    pub fn set_steer_family(&mut self, f: SteerFamily) -> Result<(), CommandError> {
        if self.steer.is_some() {
            return Err(CommandError::Steer(SteerError::Steering));
        }
        self.check_family(&f)?;
        self.steer_family = Some(f);
        Ok(())
    }

    /// The family's side tables' layouts, after `protocol::steer::check_side` for both.
    fn check_family(&self, f: &SteerFamily) -> Result<(Layout, Layout), CommandError> {
        if f.range_mrad == 0 {
            return Err(CommandError::Steer(SteerError::ZeroRange));
        }
        let slots = self.store.slots();
        let table = |slot: u8| -> Result<&[u8], CommandError> {
            if slot >= slots {
                return Err(CommandError::NoSuchSlot { slot, slots });
            }
            self.store
                .table(slot)
                .ok_or(CommandError::SlotEmpty { slot })
        };
        let parse = |slot: u8| {
            table(slot).and_then(|b| {
                GaitTable::parse(b).map_err(|error| CommandError::BadTable { slot, error })
            })
        };
        let straight = parse(f.straight)?;
        let hz = self.config.cycle_hz;
        let mut layouts = [None; 2];
        for (i, slot) in [f.left, f.right].into_iter().enumerate() {
            check_side(&straight, &parse(slot)?, slot, hz).map_err(CommandError::Steer)?;
            let checked = gait_view::check(table(slot)?)
                .map_err(|error| CommandError::BadTable { slot, error })?;
            layouts[i] = Some(checked.layout);
        }
        match layouts {
            [Some(l), Some(r)] => Ok((l, r)),
            // Both were filled above or the loop returned.
            _ => Err(CommandError::SlotEmpty { slot: f.left }),
        }
    }

    /// The descending command: from Idle or Standing a steered walk starts (endless, until
    /// `Stop`); while it ramps or walks, the heading and speed take over at the next step
    /// boundary. Refused in other states, outside the family's heading range or the speed range.
    pub fn steer(&mut self, cmd: SteerCommand) -> Result<(), CommandError> {
        let family = self
            .steer
            .map(|s| s.family)
            .or(self.steer_family)
            .ok_or(CommandError::Steer(SteerError::NoFamily))?;
        let target = blend_of(cmd.heading_mrad, family.range_mrad).map_err(CommandError::Steer)?;
        let scale = period_scale_of(cmd.speed_permille).map_err(CommandError::Steer)?;
        if let Some(s) = self.steer.as_mut() {
            let s_new = Steering {
                target,
                scale,
                ..*s
            };
            self.apply(Event::Steer)?;
            self.steer = Some(s_new);
            return Ok(());
        }
        if !matches!(self.state, State::Idle | State::Standing) {
            return Err(CommandError::WrongState(Refused {
                state: self.state,
                event: Event::Steer,
            }));
        }
        let (left, right) = self.check_family(&family)?;
        self.play(PlayParams {
            slot: family.straight,
            direction: Direction::Forward,
            period_scale: scale,
            steps: None,
        })?;
        self.steer = Some(Steering {
            family,
            left,
            right,
            blend: target,
            target,
            scale,
        });
        Ok(())
    }

    /// Signed blend playing and commanded (`protocol::steer::WEIGHT_ONE` = the left gait), while
    /// steering.
    pub fn steer_blend(&self) -> Option<(i32, i32)> {
        self.steer.map(|s| (s.blend, s.target))
    }

    /// At a step boundary of a steered walk that goes on (Walking): the blend one step towards the
    /// commanded one, the commanded speed.
    pub(crate) fn steer_at_boundary(&mut self) {
        if self.state != State::Walking {
            return;
        }
        let Some(s) = self.steer.as_mut() else { return };
        s.blend = blend_step(s.blend, s.target);
        if let Some(p) = self.play.as_mut()
            && p.scale() != u32::from(s.scale)
        {
            p.set_scale(s.scale.into());
        }
    }

    /// While steering, the period scale a boundary keeps (`SetPeriodScale` sets it too).
    pub(crate) fn steer_scale(&mut self, scale: u16) {
        if let Some(s) = self.steer.as_mut() {
            s.scale = scale;
        }
    }

    /// Goals of the gait playing at `sample` (ticks, torque-biased with `stiffness`, clamped):
    /// the selected table, or while steering its blend with a side table. How many were clamped;
    /// `None` without a table.
    pub(crate) fn sample_goals(
        &self,
        sample: Sample,
        stiffness: &[u32],
        out: &mut [i32],
        cut: &mut [bool],
    ) -> Option<usize> {
        let sel = self.selected?;
        let view = View::new(self.store.table(sel.slot)?, sel.layout);
        let Some(s) = self.steer else {
            return Some(playback::goals(
                &view,
                sample,
                &self.joints,
                stiffness,
                out,
                cut,
            ));
        };
        let (side, w) = side_of(s.blend);
        let (slot, layout) = match side {
            Side::Left => (s.family.left, s.left),
            Side::Right => (s.family.right, s.right),
        };
        let blend = Blend {
            a: view,
            b: View::new(self.store.table(slot)?, layout),
            w,
        };
        Some(playback::goals(
            &blend,
            sample,
            &self.joints,
            stiffness,
            out,
            cut,
        ))
    }
}

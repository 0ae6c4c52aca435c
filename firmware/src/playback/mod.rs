//! Playback of a step table: the gait clock (period scaling, forward or backward, a number of steps
//! or continuous), interpolation of the slices around the clock, and the torque-biased goals. The
//! slices of a table are one full step cycle, evenly spaced: slice i sits at i x period / slices and
//! the slice after the last is the first again.

use crate::bias::{JointCal, goal_ticks};

mod ramp;
pub use ramp::{Ramp, RampGroup, start_lifts};

/// Most joints a table may have (Drosophibot II has 22).
pub const MAX_JOINTS: usize = protocol::MAX_JOINTS;

/// A step table as playback reads it (implemented by [`crate::gait_view::View`] over the protocol's
/// format and by test tables). Angles in microradians, torques in mN m.
pub trait Gait {
    fn joints(&self) -> usize;
    fn slices(&self) -> usize;
    /// Step period as planned, in microseconds.
    fn period_us(&self) -> u32;
    fn angle_urad(&self, slice: usize, joint: usize) -> i32;
    fn torque_mnm(&self, slice: usize, joint: usize) -> i32;
    /// Stance flags of `slice` (bit i = leg i in LF, LM, LH, RF, RM, RH); a table without them
    /// has every leg in the air, and no leg lifts in the start ramp.
    fn stance(&self, _slice: usize) -> u8 {
        0
    }
}

/// Which way through the step the clock runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Direction {
    Forward,
    Backward,
}

/// Where the clock is: slice index and the fraction (1/65536) towards the next slice.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Sample {
    pub slice: usize,
    pub next: usize,
    pub frac: u32,
}

/// What one advance of the clock crossed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Advance {
    /// Step ends crossed (0, or 1 unless the cycle is longer than a step).
    pub steps_ended: u32,
    /// The requested number of steps is complete; the clock now rests at the step boundary.
    pub finished: bool,
}

/// The gait clock. Time inside a step is kept in table time (unscaled), so changing the scaling
/// mid-step keeps the phase.
#[derive(Debug, Clone)]
pub struct PlayClock {
    period_us: u32,
    /// Period multiplier in 1/1000: 1000 = as planned, 2000 = twice as slow.
    scale_permille: u32,
    /// Progress through the step in table microseconds, 0..period_us.
    progress_us: u32,
    /// Remainder of the scaling division, so scaling never drifts.
    rem: u64,
    direction: Direction,
    steps: Option<u32>,
    done: u32,
}

impl PlayClock {
    /// A clock at the start of a step of `period_us` (table time). `steps` = None plays on until stopped.
    pub fn new(period_us: u32, direction: Direction, steps: Option<u32>) -> Self {
        Self {
            period_us: period_us.max(1),
            scale_permille: 1000,
            progress_us: 0,
            rem: 0,
            direction,
            steps,
            done: 0,
        }
    }

    /// Sets the period scaling (1000 = as planned); takes effect from the next advance.
    pub fn set_scale(&mut self, permille: u32) {
        self.scale_permille = permille.max(1);
        self.rem = 0;
    }

    pub fn scale(&self) -> u32 {
        self.scale_permille
    }

    pub fn direction(&self) -> Direction {
        self.direction
    }

    /// Whether the run goes on until stopped (no step count).
    pub fn endless(&self) -> bool {
        self.steps.is_none()
    }

    /// Steps completed since start.
    pub fn steps_done(&self) -> u32 {
        self.done
    }

    /// Moves the clock on by `dt_us` of wall time.
    pub fn advance(&mut self, dt_us: u32) -> Advance {
        let mut adv = Advance::default();
        if self.steps.is_some_and(|s| self.done >= s) {
            adv.finished = true;
            return adv;
        }
        let num = dt_us as u64 * 1000 + self.rem;
        let dt_table = num / self.scale_permille as u64;
        self.rem = num % self.scale_permille as u64;
        let total = self.progress_us as u64 + dt_table;
        adv.steps_ended = (total / self.period_us as u64) as u32;
        self.progress_us = (total % self.period_us as u64) as u32;
        self.done = self.done.saturating_add(adv.steps_ended);
        if let Some(s) = self.steps
            && self.done >= s
        {
            self.done = s;
            self.rest_at_boundary();
            adv.finished = true;
        }
        adv
    }

    /// Puts the clock on the step boundary (slice 0): where a stopping gait ends.
    pub fn rest_at_boundary(&mut self) {
        self.progress_us = 0;
        self.rem = 0;
    }

    /// Time inside the step in table microseconds, in the direction of play (backward runs from the
    /// end of the step to its start).
    pub fn phase_us(&self) -> u32 {
        match self.direction {
            Direction::Forward => self.progress_us,
            Direction::Backward => (self.period_us - self.progress_us) % self.period_us,
        }
    }

    /// The slices around the clock for a table of `slices` slices.
    pub fn sample(&self, slices: usize) -> Sample {
        let slices = slices.max(1);
        let pos = self.phase_us() as u64 * slices as u64;
        let p = self.period_us as u64;
        let slice = (pos / p) as usize;
        Sample {
            slice,
            next: (slice + 1) % slices,
            frac: ((pos % p) * 65536 / p) as u32,
        }
    }
}

/// Linear interpolation between `a` and `b` at `frac`/65536, rounded to nearest.
pub fn lerp(a: i32, b: i32, frac: u32) -> i32 {
    let d = (b as i64 - a as i64) * frac as i64;
    (a as i64 + (d + if d >= 0 { 32768 } else { -32768 }) / 65536) as i32
}

/// Goals in ticks for the joints of `cals` at `s`, torque-biased with `stiffness` (per joint) and
/// clamped to each joint's limits; `clamped[j]` says whether joint j was cut. Returns how many were.
pub fn goals<G: Gait + ?Sized>(
    gait: &G,
    s: Sample,
    cals: &[JointCal],
    stiffness: &[u32],
    out: &mut [i32],
    clamped: &mut [bool],
) -> usize {
    let mut count = 0;
    let n = gait
        .joints()
        .min(cals.len())
        .min(out.len())
        .min(clamped.len());
    for j in 0..n {
        let angle = lerp(
            gait.angle_urad(s.slice, j),
            gait.angle_urad(s.next, j),
            s.frac,
        );
        let torque = lerp(
            gait.torque_mnm(s.slice, j),
            gait.torque_mnm(s.next, j),
            s.frac,
        );
        let k = stiffness.get(j).copied().unwrap_or(0);
        let (g, c) = goal_ticks(&cals[j], angle, torque, k);
        out[j] = g;
        clamped[j] = c;
        count += c as usize;
    }
    count
}

#[cfg(test)]
mod tests;

//! The start ramp: from the posture the robot stands in to the gait's first slice, at a bounded
//! speed. The legs that the table swings are moved in pairs, each pair in a part of the ramp of its
//! own while the other four legs stand (the middle legs, then LH with RF, then RH with LF: the four
//! feet down always surround the body). A moving leg rises by an eighth of what it rises in the
//! middle of its swing, goes across, and comes down where it goes: no foot is dragged over the
//! ground under the body's weight (a loaded foot that friction holds while its joint is asked to
//! turn is what the stuck rule calls a jam; docs/validation.md, the right turns). Joints of no leg, and every joint of a
//! table whose legs never swing (a suspended excitation, a posture change) or whose joint map does
//! not name the legs, move together in a straight line over the whole ramp.

use protocol::gait::LEGS;

use super::{Gait, MAX_JOINTS, lerp};
use crate::bias::JointCal;

/// When in the ramp a joint moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RampGroup {
    /// Over the whole ramp, in a straight line.
    Whole,
    /// In part `k` of the ramp (0-based, below [`MAX_PARTS`]), lifted; before it the joint holds
    /// where it was, after it where the gait starts.
    Part(u8),
}

/// Most parts a ramp has (a joint of a later part moves in the last).
pub const MAX_PARTS: usize = 3;

/// The legs (by their index in LF, LM, LH, RF, RM, RH) that move together, in the order of their
/// parts.
const LEG_PAIRS: [[u8; 2]; MAX_PARTS] = [[1, 4], [2, 3], [5, 0]];

/// The ramp lifts a leg by this fraction (1/N) of its swing's rise: enough to take the foot off
/// the ground (an estimate: 6 to 11 mm of the default gait's 50 to 90 mm, the rise being taken in
/// joint space), while the speed limit keeps a part short (see [`Ramp::stepping`]).
const LIFT_DIVISOR: i64 = 8;

/// One unit of ramp progress, 1/65536.
const ONE: i64 = 65536;

/// A move of every joint from where it is to where the gait starts, at a bounded speed.
#[derive(Debug, Clone)]
pub struct Ramp {
    from: [i32; MAX_JOINTS],
    to: [i32; MAX_JOINTS],
    lift: [i32; MAX_JOINTS],
    group: [RampGroup; MAX_JOINTS],
    n: usize,
    /// Start and length of each part, microseconds (all 0 when no joint is in a part).
    part_start_us: [u32; MAX_PARTS],
    part_us: [u32; MAX_PARTS],
    duration_us: u32,
    elapsed_us: u32,
}

impl Ramp {
    /// A straight ramp: the joint with the longest way moves at `speed` ticks per second, the
    /// others proportionally slower; it lasts at least `min_us`.
    pub fn new(from: &[i32], to: &[i32], speed_ticks_per_s: u32, min_us: u32) -> Self {
        Self::stepping(from, to, &[], &[], speed_ticks_per_s, min_us)
    }

    /// The ramp in parts: a joint of [`RampGroup::Part`] `k` moves in part `k` only: across (a
    /// straight line) in the part's first three quarters, raised by `lift` ticks, which it rises
    /// in the first quarter and falls in the last, so the foot lands where it goes instead of
    /// being dragged there. A [`RampGroup::Whole`] joint (and one past the end of `group`) moves
    /// straight over the whole ramp. Each part lasts as long as its slowest joint needs at `speed`
    /// ticks per second (in the first quarter it goes 4/3 of its way and 4 times its lift per part
    /// at once); the whole ramp lasts at least `min_us`, and as long as its straight joints need
    /// (the parts stretched alike when they do).
    pub fn stepping(
        from: &[i32],
        to: &[i32],
        lift: &[i32],
        group: &[RampGroup],
        speed_ticks_per_s: u32,
        min_us: u32,
    ) -> Self {
        let n = from.len().min(to.len()).min(MAX_JOINTS);
        let mut r = Self {
            from: [0; MAX_JOINTS],
            to: [0; MAX_JOINTS],
            lift: [0; MAX_JOINTS],
            group: [RampGroup::Whole; MAX_JOINTS],
            n,
            part_start_us: [0; MAX_PARTS],
            part_us: [0; MAX_PARTS],
            duration_us: 0,
            elapsed_us: 0,
        };
        r.from[..n].copy_from_slice(&from[..n]);
        r.to[..n].copy_from_slice(&to[..n]);
        let speed = u64::from(speed_ticks_per_s.max(1));
        let time_us = |ticks: u64| (ticks * 1_000_000 / speed).min(u64::from(u32::MAX / 8)) as u32;
        let mut whole_us = min_us;
        for j in 0..n {
            let way = (i64::from(r.to[j]) - i64::from(r.from[j])).unsigned_abs();
            match group.get(j).copied().unwrap_or(RampGroup::Whole) {
                RampGroup::Part(k) => {
                    let k = usize::from(k).min(MAX_PARTS - 1);
                    r.group[j] = RampGroup::Part(k as u8);
                    r.lift[j] = lift.get(j).copied().unwrap_or(0);
                    let need =
                        time_us((4 * way).div_ceil(3) + 4 * i64::from(r.lift[j]).unsigned_abs());
                    // A part with a joint in it lasts at least a cycle's worth (1 ms).
                    r.part_us[k] = r.part_us[k].max(need).max(1000);
                }
                RampGroup::Whole => whole_us = whole_us.max(time_us(way)),
            }
        }
        let parts: u32 = r.part_us.iter().sum();
        if parts < whole_us {
            // Stretch the parts alike; with none, the whole ramp is the straight joints' time.
            if parts == 0 {
                r.duration_us = whole_us;
                return r;
            }
            for p in r.part_us.iter_mut() {
                *p = (u64::from(*p) * u64::from(whole_us)).div_ceil(u64::from(parts)) as u32;
            }
        }
        let mut start = 0;
        for (s, p) in r.part_start_us.iter_mut().zip(&r.part_us) {
            *s = start;
            start += p;
        }
        r.duration_us = start;
        r
    }

    pub fn duration_us(&self) -> u32 {
        self.duration_us
    }

    /// Moves on by `dt_us`; true once the ramp has arrived.
    pub fn advance(&mut self, dt_us: u32) -> bool {
        let d = self.duration_us();
        self.elapsed_us = self.elapsed_us.saturating_add(dt_us).min(d);
        self.elapsed_us >= d
    }

    /// Goals of the ramp now (not clamped to the joints' limits: the caller does).
    pub fn goals(&self, out: &mut [i32]) {
        let progress = |start: u32, len: u32| -> i64 {
            let t = u64::from(self.elapsed_us.saturating_sub(start).min(len));
            (t * ONE as u64 / u64::from(len.max(1))) as i64
        };
        for (j, g) in out.iter_mut().enumerate().take(self.n) {
            let (along, rise) = match self.group[j] {
                RampGroup::Whole => (progress(0, self.duration_us()), 0),
                RampGroup::Part(k) => {
                    let k = usize::from(k);
                    let f = progress(self.part_start_us[k], self.part_us[k]);
                    // Across in the first three quarters; up in the first quarter, down in the
                    // last, so the foot lands where it goes, not dragged there.
                    let along = (f * 4 / 3).min(ONE);
                    let up = (4 * f).min(4 * (ONE - f)).min(ONE);
                    (along, i64::from(self.lift[j]) * up / ONE)
                }
            };
            *g = lerp(self.from[j], self.to[j], along as u32) + rise as i32;
        }
    }
}

/// The start ramp's part and lift of each joint of `gait`. A joint of leg `cals[j].leg` (0 ..= 5
/// in LF, LM, LH, RF, RM, RH; `None` for no leg) whose leg the table swings takes its pair's part
/// (`LEG_PAIRS`, counting only pairs with a leg that swings) and rises by an eighth of what it
/// rises in the middle of the leg's first swing above the straight line between its angles at
/// lift-off and touch-down (the last stance slice before the swing and the first after it), in
/// ticks of `cals`. Every other joint is [`RampGroup::Whole`] with no lift.
pub fn start_lifts<G: Gait + ?Sized>(
    gait: &G,
    cals: &[JointCal],
    lift: &mut [i32],
    group: &mut [RampGroup],
) {
    let n = gait
        .joints()
        .min(cals.len())
        .min(lift.len())
        .min(group.len());
    lift[..n].fill(0);
    group[..n].fill(RampGroup::Whole);
    if cals[..n].iter().all(|c| c.leg.is_none()) {
        // No leg named (a table of before the leg byte, a synthetic one): no need to read the
        // stance flags at all.
        return;
    }
    let swings = swings_of(gait);
    let mut part = [0u8; LEGS];
    let mut next = 0u8;
    for pair in &LEG_PAIRS {
        for &leg in pair {
            part[usize::from(leg)] = next;
        }
        next += u8::from(pair.iter().any(|&l| swings[usize::from(l)].is_some()));
    }
    for j in 0..n {
        let Some(l) = cals[j].leg.map(usize::from).filter(|&l| l < LEGS) else {
            continue;
        };
        let Some((a, m, b)) = swings[l] else {
            continue;
        };
        let ticks = |slice| {
            cals[j]
                .calibration
                .goal_of_urad(gait.angle_urad(slice, j).into())
        };
        lift[j] = ((ticks(m) - (ticks(a) + ticks(b)) / 2) / LIFT_DIVISOR) as i32;
        group[j] = RampGroup::Part(part[l]);
    }
}

/// The first swing of each leg in the table: its last stance slice before lift-off, the slice in
/// the middle of the swing and the first stance slice after it; `None` for a leg that never swings
/// or never stands. One pass over the slices' stance flags and at most one more for swings that
/// wrap past the last slice (on the board the flags are read from flash, one byte a slice).
fn swings_of<G: Gait + ?Sized>(gait: &G) -> [Option<(usize, usize, usize)>; LEGS] {
    let s = gait.slices();
    let mut lift_off = [None; LEGS];
    let mut touch_down = [None; LEGS];
    if s >= 2 {
        let mut before = gait.stance(0);
        for k in 1..=2 * s {
            let now = gait.stance(k % s);
            for leg in 0..LEGS {
                let bit = 1 << leg;
                match lift_off[leg] {
                    None if k <= s && before & bit != 0 && now & bit == 0 => {
                        lift_off[leg] = Some(k - 1)
                    }
                    Some(_) if touch_down[leg].is_none() && now & bit != 0 => {
                        touch_down[leg] = Some(k)
                    }
                    _ => {}
                }
            }
            before = now;
            let open = (0..LEGS).any(|l| lift_off[l].is_some() && touch_down[l].is_none());
            if k >= s && !open {
                break;
            }
        }
    }
    let mut out = [None; LEGS];
    for (o, (a, b)) in out.iter_mut().zip(lift_off.iter().zip(&touch_down)) {
        if let (Some(a), Some(b)) = (*a, *b) {
            let len = b - a;
            *o = Some((a, (a + len / 2) % s, b % s));
        }
    }
    out
}

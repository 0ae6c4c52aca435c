//! Continuous joint trajectories from the inverse kinematics.
//!
//! The leg IK pulls redundant legs to the resting posture in the null space, so each slice's answer
//! depends on its foot target only. Near the edge of the workspace, with joints on their limits, the
//! posture nearest rest can change branch between two slices: a step of several tenths of a radian
//! that the foot's motion does not ask for (the fly's front CTr on the ball, 0.47 rad in 2.5 ms).
//!
//! A step larger than a joint may turn in one slice (its speed limit times the slice time) is a
//! *branch change* when it is also more than twice the smallest step that reaches the next foot
//! target (the minimum-change IK from the slice before): the foot's motion does not ask for it. A
//! leg with branch changes is solved again as a continuation: each slice starts from the previous
//! one and is pulled towards the rest-optimal answer by at most half a slice's allowance per joint,
//! so the change of branch is spread over as many slices as the speed limit needs, lap after lap of
//! the periodic cycle until the cycle closes.
//!
//! Every step still over its allowance is reported ([`IkGap`], leg, slices and joint), with the
//! smallest step that would have reached the foot target: when that is over the allowance too, no
//! continuous solution within the joint limits exists at that speed (joints on their limits or a
//! footpath too fast for the limit); otherwise the continuation did not find it.

use crate::kinematics::{IkOptions, LegChain};
use crate::model::{Actuation, Model};
use nalgebra::Vector3;
use serde::Serialize;

use super::feasibility::servo_limits;

/// Steps of one joint over its allowance, in consecutive slices.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IkGap {
    pub leg: &'static str,
    pub joint: String,
    /// The first and last step over the allowance: from `first` to `first + 1`, ..., `last` to
    /// `last + 1` (cyclically).
    pub first: usize,
    pub last: usize,
    /// The largest |step| among them, rad, and the slice it starts at.
    pub step: f64,
    pub slice: usize,
    /// The smallest step of this joint that reaches the next foot target from `slice` (the
    /// minimum-change IK), rad; `None` when no solution within the limits was found from there.
    pub least: Option<f64>,
    /// What the joint may turn in one slice: speed limit x slice time, rad.
    pub bound: f64,
    /// The speed limit the bound comes from, rad/s.
    pub speed_limit: f64,
}

impl IkGap {
    /// Whether a continuous solution within the limits exists at this speed: the smallest step
    /// to the next target is within the allowance (so the IK should have found it).
    pub fn avoidable(&self) -> bool {
        self.least.is_some_and(|l| l <= self.bound)
    }
}

impl std::fmt::Display for IkGap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let slices = if self.first == self.last {
            format!("between slices {} and {}", self.first, self.first + 1)
        } else {
            format!("in slices {} to {}", self.first, self.last + 1)
        };
        write!(
            f,
            "{} {slices}: steps up to {:.3} rad (slice {}), over the {:.3} rad it may turn in one slice at {:.1} rad/s; ",
            self.joint, self.step, self.slice, self.bound, self.speed_limit
        )?;
        match self.least {
            Some(l) if l > self.bound => write!(
                f,
                "the foot target needs at least {l:.3} rad: no continuous solution within the joint limits at that speed"
            ),
            Some(l) if is_branch_change(self.step, self.least) => write!(
                f,
                "a step of {l:.3} rad would reach the foot target, but the continuation did not find a continuous path"
            ),
            Some(l) => write!(
                f,
                "a step of {l:.3} rad would reach the foot target (the pull towards the resting posture adds the rest)"
            ),
            None => write!(
                f,
                "no solution within the joint limits from the slice before"
            ),
        }
    }
}

/// The speed limit (rad/s) that bounds a joint's step per slice: the servo's no-load speed for a
/// servo; for an actuator without a datasheet (the fly's muscles) one turn per swing, 2 pi / T_sw,
/// an estimate: 62.8 rad/s at the fly's 0.1 s swing, twice its fastest joint on flat ground (the
/// front FTi, 31 rad/s); on the ball the continuation spreads the front CTr's change of branch
/// up to 99 % of it (host/planner/tests/integration/plan_ik_continuity.rs).
pub fn speed_limit(model: &Model, joint: usize, swing_s: f64) -> f64 {
    match &model.joints[joint].actuation {
        Actuation::Actuated { actuator, .. } => {
            servo_limits(*actuator).map_or(std::f64::consts::TAU / swing_s, |l| l.no_load_speed)
        }
        Actuation::Fixed { .. } => f64::INFINITY,
    }
}

/// Laps of the cycle the continuation may take to close.
const MAX_LAPS: usize = 4;
/// Shares of the full pull tried in turn, the last being no pull (the minimum-change step).
const PULL_SHARES: [f64; 4] = [1.0, 0.5, 0.25, 0.0];
/// Two laps that agree to this (rad) have closed the cycle.
const LAP_TOL: f64 = 1e-7;

/// Joint steps `q[s] -> q[s+1]` over `bound`: (slice, actuated index, step, least step to the next
/// target from `q[s]`).
fn over(
    chain: &LegChain,
    targets: &[Vector3<f64>],
    q: &[Vec<f64>],
    bound: &[f64],
    opts: &IkOptions,
) -> Vec<(usize, usize, f64, Option<f64>)> {
    let n = q.len();
    let mut out = Vec::new();
    for s in 0..n {
        let next = (s + 1) % n;
        let over: Vec<usize> = (0..bound.len())
            .filter(|&k| (q[next][k] - q[s][k]).abs() > bound[k])
            .collect();
        if over.is_empty() {
            continue;
        }
        // The minimum-change step: from q[s], pulled to q[s] itself in the null space.
        let mut c = q[s].clone();
        let least = chain
            .solve(&targets[next], &mut c, &q[s], opts)
            .ok()
            .map(|_| c);
        for k in over {
            let step = (q[next][k] - q[s][k]).abs();
            out.push((s, k, step, least.as_ref().map(|c| (c[k] - q[s][k]).abs())));
        }
    }
    out
}

/// A step over its allowance that is also more than twice the least step: a branch change.
fn is_branch_change(step: f64, least: Option<f64>) -> bool {
    least.is_none_or(|l| step > 2.0 * l)
}

/// Makes a leg's trajectory `rest_optimal` (the per-slice IK answers, actuated angles, slices
/// `dt` seconds apart in a step of swing `swing_s`) continuous where it can; returns the
/// trajectory and the gaps left.
pub fn make_continuous(
    model: &Model,
    chain: &LegChain,
    targets: &[Vector3<f64>],
    rest_optimal: Vec<Vec<f64>>,
    (swing_s, dt): (f64, f64),
    opts: &IkOptions,
) -> (Vec<Vec<f64>>, Vec<IkGap>) {
    let limits: Vec<f64> = chain
        .actuated
        .iter()
        .map(|&j| speed_limit(model, j, swing_s))
        .collect();
    let bound: Vec<f64> = limits.iter().map(|v| v * dt).collect();
    let bound = &bound[..];
    let n = rest_optimal.len();
    let first = over(chain, targets, &rest_optimal, bound, opts);
    if !first
        .iter()
        .any(|&(_, _, step, least)| is_branch_change(step, least))
    {
        let gaps = report(model, chain, &first, bound, &limits);
        return (rest_optimal, gaps);
    }
    let mut prev = rest_optimal[0].clone();
    let mut last: Option<Vec<Vec<f64>>> = None;
    let mut cur = rest_optimal.clone();
    for lap in 0..MAX_LAPS {
        for s in 0..n {
            if lap == 0 && s == 0 {
                continue;
            }
            // The strongest pull towards the rest-optimal answer (at most half an allowance per
            // joint) whose step stays within the allowance; the last try (no pull) is the
            // minimum-change step, the slowest this branch can go.
            let mut best: Option<Vec<f64>> = None;
            for share in PULL_SHARES {
                let pull: Vec<f64> = (0..prev.len())
                    .map(|k| {
                        let most = share * 0.5 * bound[k];
                        prev[k] + (rest_optimal[s][k] - prev[k]).clamp(-most, most)
                    })
                    .collect();
                let mut q = prev.clone();
                if chain.solve(&targets[s], &mut q, &pull, opts).is_err() {
                    continue;
                }
                let within = (0..q.len()).all(|k| (q[k] - prev[k]).abs() <= bound[k]);
                best = Some(q);
                if within {
                    break;
                }
            }
            // No solution from this branch within the limits: take the rest-optimal answer (a gap,
            // reported below, unless it happens to be close).
            let q = best.unwrap_or_else(|| rest_optimal[s].clone());
            cur[s] = q.clone();
            prev = q;
        }
        let closed = last.as_ref().is_some_and(|l| {
            l.iter()
                .zip(&cur)
                .all(|(a, b)| a.iter().zip(b).all(|(x, y)| (x - y).abs() < LAP_TOL))
        });
        if closed {
            break;
        }
        last = Some(cur.clone());
    }
    let gaps = report(
        model,
        chain,
        &over(chain, targets, &cur, bound, opts),
        bound,
        &limits,
    );
    (cur, gaps)
}

/// Groups steps over the allowance by joint into runs of consecutive slices.
fn report(
    model: &Model,
    chain: &LegChain,
    steps: &[(usize, usize, f64, Option<f64>)],
    bound: &[f64],
    limits: &[f64],
) -> Vec<IkGap> {
    let mut out: Vec<IkGap> = Vec::new();
    for k in 0..bound.len() {
        let joint = &model.joints[chain.actuated[k]].name;
        for &(s, _, step, least) in steps.iter().filter(|x| x.1 == k) {
            match out.last_mut() {
                Some(g) if g.joint == *joint && g.last + 1 == s => {
                    g.last = s;
                    if step > g.step {
                        (g.step, g.slice, g.least) = (step, s, least);
                    }
                }
                _ => out.push(IkGap {
                    leg: chain.leg.name(),
                    joint: joint.clone(),
                    first: s,
                    last: s,
                    step,
                    slice: s,
                    least,
                    bound: bound[k],
                    speed_limit: limits[k],
                }),
            }
        }
    }
    out
}

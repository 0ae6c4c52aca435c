//! What a walk did against its plan, the figures `dbot demo` prints per walk: the body's distance
//! per step against the plan's, and the joints' tracking error per leg.
//!
//! The plan moves the thorax at translation / stance time for the whole cycle (0.085 m / 1.5 s x
//! 2.5 s = 0.142 m per step for the servo-safe preset, as for table 1's 0.75 s of 1.25 s; 0.085 m
//! is each foot's stroke), keeps the resting body height and does not tilt or turn.

use board::record::{Row, tracking};
use physics::Figures;
use planner::model::Leg;
use planner::plan::Plan;
use protocol::Direction;

/// The body's distance of one walk against the plan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Distance {
    /// Distance walked per step in the walk's direction, m.
    pub per_step_m: f64,
    /// The plan's thorax travel per step, m.
    pub planned_m: f64,
    /// per_step / planned - 1, %.
    pub off_percent: f64,
}

/// The plan's thorax travel per step, m.
pub fn planned_per_step_m(plan: &Plan) -> f64 {
    plan.thorax_velocity.x * plan.period_s
}

/// The distance per step of a walk of `steps` steps in `direction` whose body did `f`, against
/// the plan's `planned` m per step ([`planned_per_step_m`]).
pub fn distance(f: &Figures, planned: f64, steps: u32, direction: Direction) -> Distance {
    let sign = match direction {
        Direction::Forward => 1.0,
        Direction::Backward => -1.0,
    };
    let per_step = sign * f.forward_m / f64::from(steps);
    Distance {
        per_step_m: per_step,
        planned_m: planned,
        off_percent: (per_step / planned - 1.0) * 100.0,
    }
}

/// How well one leg's joints followed the plan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LegTracking {
    pub leg: Leg,
    /// RMS over the leg's joints and cycles of present - planned angle, rad.
    pub rms_rad: f64,
    /// Largest |present - planned| of any of its joints, rad.
    pub max_abs_rad: f64,
    /// Joints of the leg in the recording.
    pub joints: usize,
}

/// Tracking error per leg over the steps after the first (the first starts from the ramp) of a
/// recording whose joints are `names`; empty when there is no step after the first.
pub fn leg_tracking(rows: &[Row], names: &[String]) -> Vec<LegTracking> {
    let rows: Vec<Row> = rows.iter().filter(|r| r.step >= 1).cloned().collect();
    if rows.is_empty() {
        return Vec::new();
    }
    let per_joint = tracking(&rows, names.len());
    Leg::ALL
        .into_iter()
        .filter_map(|leg| {
            let mine: Vec<_> = per_joint
                .iter()
                .filter(|t| {
                    names
                        .get(t.joint)
                        .is_some_and(|n| n.starts_with(leg.name()))
                })
                .collect();
            if mine.is_empty() {
                return None;
            }
            let n: usize = mine.iter().map(|t| t.samples).sum();
            let sq: f64 = mine
                .iter()
                .map(|t| t.rms_rad * t.rms_rad * t.samples as f64)
                .sum();
            Some(LegTracking {
                leg,
                rms_rad: (sq / n.max(1) as f64).sqrt(),
                max_abs_rad: mine.iter().map(|t| t.max_abs_rad).fold(0.0, f64::max),
                joints: mine.len(),
            })
        })
        .collect()
}

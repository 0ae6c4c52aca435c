//! A planned curve checked on the physics robot: the turn per step and the radius the thorax
//! walks, measured from its path, against the plan's.
//!
//! The plan moves the thorax at constant velocity v (x, thorax frame) and yaw rate w, so between
//! two step boundaries the thorax frame turns by the plan's turn per step w T about a fixed point,
//! the instantaneous centre (0, v / w) of the thorax frame. The measurement takes the thorax pose
//! at step boundaries (the same phase of the cycle, so the body's sway within a step cancels),
//! the turn as the yaw change between them, and the centre as the fixed point of the rigid motion
//! from the first boundary's pose to the last's: the signed radius is its distance from the thorax,
//! positive on the left.

use std::time::Duration;

use physics::{Figures, PhysicsRobot, WalkLog};
use planner::gait::StepParams;
use planner::model::Model;
use planner::plan::Plan;
use protocol::{PlayCommand, Steps};

use crate::error::{Context, Result};
use crate::physics_walk::{BodyWalk, Follow, Walk, start_figures, walk_and_record};

/// Bus cycles between two logged poses of a measured walk: the measurement needs the thorax of
/// every cycle, not the joints.
const POSE_EVERY_CYCLES: usize = 100_000;
/// How often a measured walk is looked at, simulated time.
const POLL: Duration = Duration::from_millis(250);

/// The curve a plan walks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlannedTurn {
    /// Thorax yaw per step cycle, rad, positive left.
    pub turn_per_step_rad: f64,
    /// Signed radius of the thorax's path, m (centre on the left positive); `None`: straight.
    pub radius_m: Option<f64>,
}

impl PlannedTurn {
    /// The plan's curve from its thorax velocity and yaw rate (flat ground or an incline).
    pub fn of(plan: &Plan) -> PlannedTurn {
        let w = plan.thorax_angular_velocity.z;
        PlannedTurn {
            turn_per_step_rad: w * plan.period_s,
            radius_m: (w != 0.0).then(|| plan.thorax_velocity.x / w),
        }
    }
}

/// The curve the thorax walked between two step boundaries.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeasuredTurn {
    /// Whole steps measured.
    pub steps: u32,
    /// Mean yaw change per step, rad, positive left.
    pub turn_per_step_rad: f64,
    /// Signed distance of the turning centre from the thorax, m, positive on the left (sign of
    /// the centre's y in the thorax frame).
    pub radius_m: f64,
    /// How far the centre lies ahead of the thorax (x in the thorax frame), m: 0 in the plan.
    pub centre_ahead_m: f64,
}

/// Yaw of a unit quaternion (w, x, y, z), rad.
fn yaw(q: [f64; 4]) -> f64 {
    let [w, x, y, z] = q;
    (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z))
}

fn wrap(a: f64) -> f64 {
    a.sin().atan2(a.cos())
}

/// The thorax's yaw change from the log's first sample to its last, unwrapped (so more than a
/// half turn counts whole), rad.
pub fn heading_change(log: &WalkLog) -> f64 {
    log.samples
        .windows(2)
        .map(|w| wrap(yaw(w[1].thorax.1) - yaw(w[0].thorax.1)))
        .sum()
}

/// Thorax (x, y, unwrapped yaw) at the first sample of each step `from..=to` of `log` (the first
/// bus cycle whose playback has completed that many steps); `None` if the log lacks one.
pub fn boundary_poses(log: &WalkLog, from: u32, to: u32) -> Option<Vec<[f64; 3]>> {
    let mut out = Vec::new();
    let mut unwrapped = 0.0;
    let mut last_yaw: Option<f64> = None;
    let mut next = from;
    for s in &log.samples {
        let y = yaw(s.thorax.1);
        if let Some(l) = last_yaw {
            unwrapped += wrap(y - l);
        } else {
            unwrapped = y;
        }
        last_yaw = Some(y);
        let Some((step, _)) = s.playback else {
            continue;
        };
        if next <= to && step >= next {
            if step > next {
                // The log skipped a boundary (a step shorter than one sample).
                return None;
            }
            out.push([s.thorax.0[0], s.thorax.0[1], unwrapped]);
            next += 1;
        }
    }
    (next > to).then_some(out)
}

/// The curve between step boundaries `from` and `to` (`to > from`) of `log`.
pub fn measure_turn(log: &WalkLog, from: u32, to: u32) -> Option<MeasuredTurn> {
    if to <= from {
        return None;
    }
    let poses = boundary_poses(log, from, to)?;
    let ([x0, y0, a0], [x1, y1, a1]) = (poses[0], poses[poses.len() - 1]);
    let turn = a1 - a0;
    // The fixed point C of p -> R(turn) (p - p0) + p1... i.e. p1 = C + R (p0 - C):
    // (I - R) C = p1 - R p0, solved in closed form (det = 2 - 2 cos turn).
    let (c, s) = (turn.cos(), turn.sin());
    let (bx, by) = (x1 - (c * x0 - s * y0), y1 - (s * x0 + c * y0));
    let det = (1.0 - c) * (1.0 - c) + s * s;
    let (cx, cy) = if det < 1e-12 {
        // No turn: the centre is at infinity.
        (f64::NAN, f64::NAN)
    } else {
        (
            ((1.0 - c) * bx - s * by) / det,
            (s * bx + (1.0 - c) * by) / det,
        )
    };
    // The centre in the first boundary's thorax frame.
    let (dx, dy) = (cx - x0, cy - y0);
    let (ca, sa) = (a0.cos(), a0.sin());
    let (ahead, left) = (ca * dx + sa * dy, -sa * dx + ca * dy);
    Some(MeasuredTurn {
        steps: to - from,
        turn_per_step_rad: turn / f64::from(to - from),
        radius_m: left.signum() * ahead.hypot(left),
        centre_ahead_m: ahead,
    })
}

/// A curve walked on the physics robot against its plan.
#[derive(Debug, Clone)]
pub struct TurnWalk {
    pub planned: PlannedTurn,
    pub measured: MeasuredTurn,
    /// What the walk did to the body (heading over the whole walk, slip, sag).
    pub figures: Figures,
}

/// The step table of `plan` as `dbot table --plan` builds it: the walks' inverse dynamics as the
/// torque bias, every rule of an upload checked.
pub fn walk_table(plan: &Plan, name: &str) -> Result<board::rules::build::CheckedTable> {
    let cycle = crate::walk::solve_walk_dynamics(plan)?;
    let torques = planner::dynamics::output::torque_rows(&cycle);
    let table = board::rules::build::plan_table(plan, Some(&torques), name, Default::default())
        .with_context(|| format!("the step table `{name}`"))?;
    Ok(table)
}

/// Plans `params` for `model`, walks `steps` steps (at least 2) forward on a fresh physics robot
/// on flat ground, and measures the curve over the steps after the first (the first starts the
/// body moving from standing).
pub fn walk_turn(model: &Model, params: &StepParams, steps: u32) -> Result<TurnWalk> {
    if steps < 2 {
        crate::bail!(
            "steps {steps}: a curve is measured over the steps after the first, give 2 or more"
        );
    }
    let plan = planner::plan::plan(model, params)
        .with_context(|| format!("planning a step of {}", model.name))?;
    let table = walk_table(&plan, "turn")?;
    let robot = PhysicsRobot::new(model, &planner::terrain::Ground::Flat)?;
    let walk = Walk {
        tables: vec![(0, table.bytes())],
        play: PlayCommand::forward(0, Steps::Count(steps)),
        queue: Vec::new(),
        what: format!("the curve of {steps} steps"),
    };
    let follow = Follow::generous(POLL, f64::from(steps) * plan.period_s);
    let BodyWalk { figures, log } = walk_and_record(
        robot,
        &walk,
        follow,
        |b| start_figures(b, POSE_EVERY_CYCLES),
        |_, _| Ok(()),
    )?;
    let measured = measure_turn(&log, 1, steps)
        .with_context(|| format!("the walk's log lacks step boundaries 1 to {steps}"))?;
    Ok(TurnWalk {
        planned: PlannedTurn::of(&plan),
        measured,
        figures,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use physics::WalkSample;

    /// A log of a thorax on a circle about (cx, cy) of signed radius `r` (centre on its left),
    /// turning by `per_step` rad per step of 50 samples, starting at heading `a0`.
    fn circle_log(centre: (f64, f64), r: f64, a0: f64, per_step: f64, steps: u32) -> WalkLog {
        let n = 50 * steps;
        let samples = (0..=n)
            .map(|i| {
                let a = a0 + per_step * f64::from(i) / 50.0;
                // The thorax is at the centre minus r times its left unit vector (-sin a, cos a).
                let p = [centre.0 + r * a.sin(), centre.1 - r * a.cos(), 0.2];
                let q = [(a / 2.0).cos(), 0.0, 0.0, (a / 2.0).sin()];
                WalkSample {
                    time_s: f64::from(i) * 0.01,
                    playback: Some((i / 50, (i % 50) as u16)),
                    walking: true,
                    thorax: (p, q),
                    foot_forces: vec![],
                    foot_spheres: vec![],
                    pose: None,
                    strain: None,
                }
            })
            .collect();
        WalkLog {
            pose_every: 1,
            samples,
        }
    }

    #[test]
    fn a_circle_gives_its_radius_and_turn_left_and_right() {
        // 20 deg per step on 0.6 m, left; and 15 deg per step to the right on 0.9 m (centre on the
        // right, the yaw clockwise), across the +-pi wrap of the heading.
        for (r, per_step, a0) in [
            (0.6, 20f64.to_radians(), 0.3),
            (-0.9, -15f64.to_radians(), 3.0),
        ] {
            let log = circle_log((1.0, -2.0), r, a0, per_step, 8);
            let m = measure_turn(&log, 1, 7).unwrap();
            assert_eq!(m.steps, 6);
            assert!((m.turn_per_step_rad - per_step).abs() < 1e-9, "{m:?}");
            assert!((m.radius_m - r).abs() < 1e-9, "{m:?}");
            assert!(m.centre_ahead_m.abs() < 1e-9, "{m:?}");
        }
    }

    #[test]
    fn turning_on_the_spot_has_radius_zero_and_straight_none() {
        let log = circle_log((0.4, 0.1), 0.0, -1.0, 0.2, 4);
        let m = measure_turn(&log, 1, 3).unwrap();
        assert!((m.turn_per_step_rad - 0.2).abs() < 1e-9);
        assert!(m.radius_m.abs() < 1e-9, "{m:?}");
        // Straight: a radius of 1e6 m is a line here; no turn leaves the centre undefined.
        let mut log = circle_log((0.0, 1e6), 1e6, 0.0, 0.0, 3);
        for (i, s) in log.samples.iter_mut().enumerate() {
            s.thorax.0 = [0.01 * i as f64, 0.0, 0.2];
        }
        let m = measure_turn(&log, 1, 2).unwrap();
        assert_eq!(m.turn_per_step_rad, 0.0);
        assert!(m.radius_m.is_nan());
    }

    #[test]
    fn missing_boundaries_measure_nothing() {
        let log = circle_log((0.0, 0.0), 0.5, 0.0, 0.1, 3);
        assert_eq!(measure_turn(&log, 1, 5), None);
        assert_eq!(measure_turn(&log, 2, 2), None);
    }
}

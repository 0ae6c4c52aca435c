//! What a perturbation does, measured on the physics robot: the gait walked with the lab's
//! platform ([`physics::Platform`]) under one foot, and that leg's load (its foot's normal
//! contact force) at the start of every step, so the perturbed step stands against the others.

use std::time::Duration;

use board::link::Board;
use physics::{Figures, PhysicsRobot, Platform, Substrate, WalkLog};
use planner::terrain::Ground;
use protocol::{Direction, PlayCommand, RunState, Steps};

use crate::error::Result;

/// The window at each step's start in which the leg's load is read: the platform's two cycles up
/// and its way back down at the profile velocity fit well inside, s.
pub const WINDOW_S: f64 = 0.15;

/// One step of a perturbed walk, for the platform's leg.
#[derive(Debug, Clone, PartialEq)]
pub struct StepLoad {
    /// Whole steps walked before it.
    pub step: u32,
    /// Largest and mean normal force on the leg's foot in the first [`WINDOW_S`] of the step, N.
    pub peak_n: f64,
    pub mean_n: f64,
}

/// A walk with the platform.
#[derive(Debug, Clone, PartialEq)]
pub struct PerturbedWalk {
    pub platform: Platform,
    pub steps: Vec<StepLoad>,
    /// The platform's highest top over the walk, m.
    pub platform_peak_m: f64,
    pub figures: Figures,
}

impl PerturbedWalk {
    /// The perturbed step's load.
    pub fn perturbed(&self) -> Option<&StepLoad> {
        self.steps.iter().find(|s| s.step == self.platform.step)
    }

    /// The larger peak load of the steps just before and after the perturbed one, N (the first
    /// steps after the start still settle from the standing posture).
    pub fn unperturbed_peak_n(&self) -> f64 {
        let k = self.platform.step;
        self.steps
            .iter()
            .filter(|s| s.step + 1 == k || s.step == k + 1)
            .map(|s| s.peak_n)
            .fold(0.0, f64::max)
    }
}

/// Walks `table` forward for `steps` steps on a fresh physics robot on `scene` (sand paper) with
/// `platform`;
/// refuses a perturbation step beyond the run's steps before anything moves, and fails if the
/// robot faults.
pub fn walk_perturbed(
    table: &[u8],
    scene: &Ground,
    platform: Platform,
    steps: u32,
) -> Result<PerturbedWalk> {
    if platform.step >= steps {
        crate::bail!(
            "perturbation step {} is beyond the run's {steps} steps (steps count from 0: at most {})",
            platform.step,
            steps.saturating_sub(1)
        );
    }
    // Where the leg's foot stands when the step starts: the same walk without the platform
    // (the physics robot is deterministic) is scouted first.
    let mut scout = PhysicsRobot::drosophibot(scene)?;
    scout.start_log(1_000_000);
    let (_, log, _) = walk_logged(scout, table, steps)?;
    let at = log
        .samples
        .iter()
        .find(|s| s.walking && s.playback.is_some_and(|(done, _)| done == platform.step))
        .and_then(|s| s.foot_spheres.iter().find(|(l, _)| *l == platform.leg))
        .map(|(_, p)| [p[0], p[1]])
        .ok_or_else(|| crate::LabError::invalid("the scouting walk never reached the step"))?;
    let mut robot = PhysicsRobot::with_platform(scene, Substrate::Sandpaper, platform, at)?;
    robot.start_log(1_000_000);
    let (figures, log, platform_peak_m) = walk_logged(robot, table, steps)?;
    Ok(PerturbedWalk {
        platform,
        steps: step_loads(&log, &platform),
        platform_peak_m,
        figures,
    })
}

/// Walks `robot` through `table` for `steps` steps; its figures, its log and the platform's
/// highest top (m, 0 without one).
fn walk_logged(robot: PhysicsRobot, table: &[u8], steps: u32) -> Result<(Figures, WalkLog, f64)> {
    let mut b = Board::connect(robot.into_transport())?;
    b.upload(0, table, |_, _| {})?;
    b.play(PlayCommand {
        slot: 0,
        direction: Direction::Forward,
        period_scale: protocol::units::PERIOD_SCALE_ONE,
        steps: Steps::Count(steps),
    })?;
    let period_s = f64::from(protocol::GaitTable::parse(table)?.header().step_period_us) * 1e-6;
    // One bus cycle a poll; the bound only ends a gait that never stops.
    let polls = ((f64::from(steps) + 3.0) * period_s / 0.01).ceil() as u32;
    let mut platform_peak_m: f64 = 0.0;
    for _ in 0..polls {
        b.wait(Duration::from_millis(10))?;
        let r = b.transport().robot();
        if let Some((_, h)) = r.servos().platform_state() {
            platform_peak_m = platform_peak_m.max(h);
        }
        let c = r.controller();
        if c.state() == firmware::safety::State::Standing && c.playback().is_none() {
            break;
        }
    }
    let s = b.status()?;
    if let Some(fault) = s.fault {
        crate::bail!("the perturbed walk faulted: {fault}");
    }
    if s.state != RunState::Standing {
        crate::bail!("the perturbed walk did not end standing");
    }
    let robot = b.transport_mut().robot_mut().servos_mut();
    let figures = robot
        .figures()
        .cloned()
        .ok_or_else(|| crate::LabError::invalid("the physics robot sampled nothing"))?;
    let log = robot.take_log().unwrap_or_default();
    Ok((figures, log, platform_peak_m))
}

/// The leg's load in the first [`WINDOW_S`] of each step the log walked.
fn step_loads(log: &WalkLog, platform: &Platform) -> Vec<StepLoad> {
    let mut out: Vec<(u32, f64, Vec<f64>)> = Vec::new();
    for s in log.samples.iter().filter(|s| s.walking) {
        let Some((done, _)) = s.playback else {
            continue;
        };
        let fz = s
            .foot_forces
            .iter()
            .find(|(l, _)| *l == platform.leg)
            .map_or(0.0, |(_, f)| f[2]);
        match out.last_mut() {
            Some((d, t0, v)) if *d == done => {
                if s.time_s - *t0 < WINDOW_S {
                    v.push(fz);
                }
            }
            _ => out.push((done, s.time_s, vec![fz])),
        }
    }
    out.into_iter()
        .map(|(step, _, v)| StepLoad {
            step,
            peak_n: v.iter().copied().fold(0.0, f64::max),
            mean_n: v.iter().sum::<f64>() / v.len() as f64,
        })
        .collect()
}

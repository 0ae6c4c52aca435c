//! What a perturbation does, measured on the physics robot: the gait walked with the lab's
//! platform under one foot, set up on the board as a trial sets it up
//! (`Board::set_platform`: the firmware moves the platform's servo, the physics robot's slide
//! follows that servo, `physics::platform`), and that leg's load (its foot's normal contact
//! force) at the start of every step, so the perturbed step stands against the others.

use board::platform::{Perturb, default_platform_id};
use physics::{Figures, PhysicsRobot, PlatformPlace, Substrate, WalkLog};
use planner::model::Leg;
use planner::terrain::Ground;
use protocol::PlatformMove;

use crate::error::Result;
use crate::physics_walk::walk_forward;

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
    pub perturb: Perturb,
    pub steps: Vec<StepLoad>,
    /// The platform's highest top over the walk, m.
    pub platform_peak_m: f64,
    pub figures: Figures,
}

impl PerturbedWalk {
    /// The perturbed step's load.
    pub fn perturbed(&self) -> Option<&StepLoad> {
        self.steps
            .iter()
            .find(|s| s.step == self.perturb.setup.step)
    }

    /// The larger peak load of the steps just before and after the perturbed one, N (the first
    /// steps after the start still settle from the standing posture).
    pub fn unperturbed_peak_n(&self) -> f64 {
        let k = self.perturb.setup.step;
        self.steps
            .iter()
            .filter(|s| s.step + 1 == k || s.step == k + 1)
            .map(|s| s.peak_n)
            .fold(0.0, f64::max)
    }
}

/// The lab's rising platform under `leg` at `step`, on the ID the built-in robot leaves free
/// ([`default_platform_id`] of its joints' servos: 23).
pub fn lab_rise(leg: Leg, step: u32) -> Perturb {
    let ids: Vec<u8> = board::robot::robot_servos()
        .iter()
        .map(|(id, _)| *id)
        .collect();
    let mut p = Perturb::lab(leg, step, PlatformMove::Rise);
    p.setup.servo_id = default_platform_id(&ids);
    p
}

/// Walks `table` forward for `steps` steps on a fresh physics robot on `scene` (sand paper) with
/// the platform of `perturb` under its leg, set up through `Board::set_platform` after the
/// upload as the CLI does (the schedule is the firmware's); refuses a perturbation step beyond
/// the run's steps before anything moves, and fails if the robot faults.
pub fn walk_perturbed(
    table: &[u8],
    scene: &Ground,
    perturb: Perturb,
    steps: u32,
) -> Result<PerturbedWalk> {
    let setup = perturb.setup;
    if setup.step >= steps {
        crate::bail!(
            "perturbation step {} is beyond the run's {steps} steps (steps count from 0: at most {})",
            setup.step,
            steps.saturating_sub(1)
        );
    }
    // The box waits beside the robot and goes under the leg's foot when the firmware first
    // moves its servo (the perturbed step's first cycle): `physics::PlatformPlace`.
    let mut robot = PhysicsRobot::with_platform(
        scene,
        Substrate::Sandpaper,
        setup.servo_id,
        PlatformPlace::UnderFootOf(perturb.leg),
    )?;
    robot.start_log(1_000_000);
    let mut platform_peak_m: f64 = 0.0;
    let walk = walk_forward(
        robot,
        table,
        steps,
        "the perturbed walk",
        |b| Ok(b.set_platform(setup)?),
        |r| {
            if let Some((_, h)) = r.platform_state() {
                platform_peak_m = platform_peak_m.max(h);
            }
        },
    )?;
    Ok(PerturbedWalk {
        perturb,
        steps: step_loads(&walk.log, perturb.leg),
        platform_peak_m,
        figures: walk.figures,
    })
}

/// The leg's load in the first [`WINDOW_S`] of each step the log walked.
fn step_loads(log: &WalkLog, leg: Leg) -> Vec<StepLoad> {
    let mut out: Vec<(u32, f64, Vec<f64>)> = Vec::new();
    for s in log.samples.iter().filter(|s| s.walking) {
        let Some((done, _)) = s.playback else {
            continue;
        };
        let fz = s
            .foot_forces
            .iter()
            .find(|(l, _)| *l == leg)
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

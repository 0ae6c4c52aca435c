//! What a substrate changes: the same gait walked on fresh physics robots on two (or more)
//! substrates, each walk's slip per foot (horizontal travel of a loaded foot, the physics robot's
//! [`Figures`]) and thorax travel per step. A foot slides when its tangential force would exceed
//! mu times its normal force, so a lower mu ([`physics::substrate::friction`], ESTIMATES) caps
//! the traction a foot gets; over a few steps slip is not monotonic in mu (docs/validation.md).

use physics::{Figures, PhysicsRobot, Substrate, WalkLog};
use planner::model::Leg;
use planner::terrain::Ground;

use crate::error::Result;
use crate::physics_walk::{BodyWalk, walk_forward};

/// One walk on one substrate.
#[derive(Debug, Clone, PartialEq)]
pub struct SubstrateWalk {
    pub substrate: Substrate,
    /// The feet's sliding friction coefficient on it (ESTIMATE).
    pub mu: f64,
    /// Horizontal travel of each foot while loaded, m (model feet order).
    pub slip_m: Vec<(Leg, f64)>,
    /// Per foot, the largest ratio of tangential to normal contact force while it was loaded
    /// (normal force over 1 N): Coulomb's law holds it at or below mu.
    pub traction_max: Vec<(Leg, f64)>,
    /// Thorax travel forward over the walk, m, and per step.
    pub forward_m: f64,
    pub per_step_m: f64,
    /// Everything the physics robot measured (heading, height, tilt, saturated servos).
    pub figures: Figures,
}

impl SubstrateWalk {
    /// The slip of `leg`'s foot, m.
    pub fn slip(&self, leg: Leg) -> f64 {
        self.slip_m
            .iter()
            .find(|(l, _)| *l == leg)
            .map_or(0.0, |(_, s)| *s)
    }

    /// The slip of all six feet together, m.
    pub fn total_slip_m(&self) -> f64 {
        self.slip_m.iter().map(|(_, s)| s).sum()
    }
}

/// Walks the step table `table` forward for `steps` steps from power-on on `terrain` once per
/// substrate, each on a fresh physics robot (Drosophibot II).
/// A walk that faults is an error naming the substrate and the fault.
pub fn walk_on_substrates(
    table: &[u8],
    terrain: &Ground,
    substrates: &[Substrate],
    steps: u32,
) -> Result<Vec<SubstrateWalk>> {
    if steps == 0 {
        crate::bail!("steps 0: give at least one step");
    }
    substrates
        .iter()
        .map(|&substrate| walk_on(table, terrain, substrate, steps))
        .collect()
}

fn walk_on(
    table: &[u8],
    terrain: &Ground,
    substrate: Substrate,
    steps: u32,
) -> Result<SubstrateWalk> {
    let mut robot = PhysicsRobot::drosophibot_on(terrain, substrate)?;
    // Poses are not needed: one every 10^6 cycles keeps the log to forces and positions.
    robot.start_log(1_000_000);
    let mu = physics::substrate::friction(substrate);
    let what = format!("walking on {}", substrate.name());
    let BodyWalk { figures, log } = walk_forward(robot, table, steps, &what, |_| Ok(()), |_| {})?;
    Ok(SubstrateWalk {
        substrate,
        mu,
        slip_m: figures.slip_m.clone(),
        traction_max: traction_max(&log),
        forward_m: figures.forward_m,
        per_step_m: figures.forward_m / f64::from(steps),
        figures,
    })
}

/// A foot carries weight above this normal force, N (as the physics robot's slip figure counts it).
const LOADED_N: f64 = 1.0;

/// Per foot, the largest |F_t| / F_n over the loaded samples of `log`.
fn traction_max(log: &WalkLog) -> Vec<(Leg, f64)> {
    let Some(first) = log.samples.first() else {
        return Vec::new();
    };
    first
        .foot_forces
        .iter()
        .enumerate()
        .map(|(i, &(leg, _))| {
            let max = log
                .samples
                .iter()
                .filter_map(|s| s.foot_forces.get(i))
                .filter(|(_, f)| f[2] > LOADED_N)
                .map(|(_, f)| f[0].hypot(f[1]) / f[2])
                .fold(0.0, f64::max);
            (leg, max)
        })
        .collect()
}

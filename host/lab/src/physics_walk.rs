//! One walk of a step table on a fresh physics robot, as the lab's body measurements take it
//! (substrates, walking strain, the perturbation platform): the table uploaded into slot 0,
//! played forward for whole steps at its planned period, followed one bus cycle at a time until
//! the firmware stands again. A fault, or a walk still going well after its steps should have
//! ended, is an error that names the walk; the body's figures and log are what it returns.

use std::time::Duration;

use board::link::Board;
use physics::{Figures, PhysicsRobot, PhysicsTransport, WalkLog};
use protocol::{PlayCommand, RunState, Steps};

use crate::error::Result;

/// One bus cycle at the physics robot's 100 Hz: how often the walk is looked at.
const POLL: Duration = Duration::from_millis(10);

/// What the physics robot measured over a walk.
#[derive(Debug, Clone)]
pub struct BodyWalk {
    pub figures: Figures,
    /// The log, as [`PhysicsRobot::start_log`] asked for before the walk (empty without one).
    pub log: WalkLog,
}

/// Walks `table` forward for `steps` steps on `robot` (start its log first if the log is
/// wanted). `before_play` runs after the upload, before the walk starts (a platform set up, the
/// bias switched off); `each_cycle` sees the robot after every bus cycle. `what` names the walk
/// in its errors ("walking on wire mesh", "the strain walk").
pub fn walk_forward(
    robot: PhysicsRobot,
    table: &[u8],
    steps: u32,
    what: &str,
    before_play: impl FnOnce(&mut Board<PhysicsTransport>) -> Result<()>,
    mut each_cycle: impl FnMut(&PhysicsRobot),
) -> Result<BodyWalk> {
    let period_s = f64::from(protocol::GaitTable::parse(table)?.header().step_period_us) * 1e-6;
    let mut b = Board::connect(robot.into_transport())?;
    let checked = crate::simulated::checked(table, what)?;
    b.upload(0, &checked, |_, _| {})?;
    before_play(&mut b)?;
    crate::simulated::play(
        &mut b,
        PlayCommand::forward(0, Steps::Count(steps)),
        Some(&checked),
    )?;
    // Simulated time: `steps` periods after a start ramp; the bound only ends a gait that never
    // stops.
    let cycles = ((f64::from(steps) + 3.0) * period_s / POLL.as_secs_f64()).ceil() as u32;
    for _ in 0..cycles {
        b.wait(POLL)?;
        let r = b.transport().robot();
        each_cycle(r.servos());
        let c = r.controller();
        if c.state() == firmware::safety::State::Standing && c.playback().is_none() {
            break;
        }
    }
    let s = b.status()?;
    if let Some(fault) = s.fault {
        crate::bail!("{what}: the robot faulted: {fault}");
    }
    if s.state != RunState::Standing {
        crate::bail!(
            "{what}: the robot still walks {:.1} s after its {steps} steps should have ended",
            f64::from(cycles) * POLL.as_secs_f64()
        );
    }
    let robot = b.transport_mut().robot_mut().servos_mut();
    let figures = robot.figures().cloned().ok_or_else(|| {
        crate::LabError::invalid(format!("{what}: the physics robot sampled nothing"))
    })?;
    let log = robot.take_log().unwrap_or_default();
    Ok(BodyWalk { figures, log })
}

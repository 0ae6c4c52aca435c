//! The one walk of the lab's body measurements on a fresh physics robot (a planned curve,
//! `walk_turn`; a run of queued gaits, `walk_sequence`; the substrates, the walking strain and
//! the perturbation platform, [`walk_forward`]): the step tables uploaded, the first gait played
//! from standing and the others queued behind it, the board's status polled until the firmware
//! stands again (or for a fixed span, after which it must stand), a callback seeing the board at
//! every poll. A fault, or a walk still going well after it should have ended, is an error that
//! names the walk; the body's figures and log are what it records.
//!
//! A status request takes no simulated time, so how often a walk is polled moves nothing in the
//! body; it and [`End`] decide only how long after the walk's end the robot still stands in the
//! figures.

use std::time::Duration;

use board::link::Board;
use physics::{Figures, PhysicsRobot, PhysicsTransport, WalkLog};
use protocol::{PlayCommand, QueueCommand, RunState, Status, Steps};

use crate::error::{Context, LabError, Result};

/// One bus cycle at the physics robot's 100 Hz: how often [`walk_forward`] looks at the walk.
const POLL: Duration = Duration::from_millis(10);

/// What the physics robot measured over a walk.
#[derive(Debug, Clone)]
pub struct BodyWalk {
    pub figures: Figures,
    /// The log, as [`PhysicsRobot::start_log`] asked for before the walk (empty without one).
    pub log: WalkLog,
}

/// What a walk plays.
#[derive(Debug, Clone)]
pub struct Walk<'a> {
    /// Step tables and the slot each goes into, uploaded in this order.
    pub tables: Vec<(u8, &'a [u8])>,
    /// The gait played from standing.
    pub play: PlayCommand,
    /// The gaits queued behind it (`Board::queue_gait`), in order.
    pub queue: Vec<PlayCommand>,
    /// What the walk is called in its errors ("walking on wire mesh", "the strain walk").
    pub what: String,
}

/// How a walk is followed: a look at the board's status every `every` of simulated time, for at
/// most `limit_s`; the walk ends as `end` says (by the limit the robot must stand again).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Follow {
    pub every: Duration,
    pub limit_s: f64,
    pub end: End,
}

/// When a followed walk ends.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum End {
    /// At the first look that finds the robot standing again after it was seen playing.
    Standing,
    /// At `limit_s`, a fixed span of simulated time (the body's figures cover all of it, the
    /// robot standing still after its steps included).
    Limit,
}

impl Follow {
    /// A look every `every` for a walk of about `walk_s` simulated seconds, until the robot
    /// stands, for at most a generous 2 x `walk_s` + 5 s.
    pub fn generous(every: Duration, walk_s: f64) -> Self {
        Self {
            every,
            limit_s: 2.0 * walk_s + 5.0,
            end: End::Standing,
        }
    }
}

/// Uploads `walk`'s tables to a board on `robot` (start its log first if the log is wanted),
/// runs `before_play` (a platform set up, the bias switched off, the figures started afresh),
/// plays `walk.play` and queues `walk.queue` behind it, then follows the walk as `follow` says
/// (the robot standing again after it was seen playing, at the latest by `follow.limit_s`);
/// `each_poll` sees the board and its status at every look, the last one included. Returns what
/// the body measured.
pub fn walk_and_record(
    robot: PhysicsRobot,
    walk: &Walk<'_>,
    follow: Follow,
    before_play: impl FnOnce(&mut Board<PhysicsTransport>) -> Result<()>,
    mut each_poll: impl FnMut(&mut Board<PhysicsTransport>, &Status) -> Result<()>,
) -> Result<BodyWalk> {
    let what = &walk.what;
    let mut b = Board::connect(robot.into_transport())?;
    // Every table and command through the rules, as every door (`crate::simulated`).
    let mut checked = Vec::with_capacity(walk.tables.len());
    for &(slot, table) in &walk.tables {
        let t = crate::simulated::checked(table, what)?;
        b.upload(slot, &t, |_, _| {})?;
        checked.push((slot, t));
    }
    let table_of = |slot: u8| checked.iter().find(|(s, _)| *s == slot).map(|(_, t)| t);
    before_play(&mut b)?;
    crate::simulated::play(&mut b, walk.play, table_of(walk.play.slot))?;
    for (i, &next) in walk.queue.iter().enumerate() {
        crate::simulated::queue(&mut b, QueueCommand(next), table_of(next.slot))
            .with_context(|| format!("{what}: queueing gait {} after the one before", i + 2))?;
    }
    let polls = (follow.limit_s / follow.every.as_secs_f64()).ceil() as u32;
    let mut walked = false;
    let mut stood = false;
    for _ in 0..polls {
        b.wait(follow.every)?;
        let st = b.status()?;
        if let Some(fault) = st.fault {
            crate::bail!("{what}: the robot faulted: {fault}");
        }
        walked |= st.playback.is_some();
        each_poll(&mut b, &st)?;
        stood = walked && st.playback.is_none() && st.state == RunState::Standing;
        if stood && follow.end == End::Standing {
            // One look more, so the log holds a cycle after the run ended (its last step
            // boundary), whatever the look's phase against the step.
            b.wait(follow.every)?;
            break;
        }
    }
    if !stood {
        crate::bail!(
            "{what}: the robot still walks {:.1} s after the walk started, well after it should have ended",
            follow.limit_s
        );
    }
    let robot = b.transport_mut().robot_mut().servos_mut();
    let figures = robot
        .figures()
        .cloned()
        .ok_or_else(|| LabError::invalid(format!("{what}: the physics robot sampled nothing")))?;
    let log = robot.take_log().unwrap_or_default();
    Ok(BodyWalk { figures, log })
}

/// Starts the body's figures and a log of a pose every `pose_every` bus cycles afresh (after the
/// upload, as a measured walk starts): a `before_play` of [`walk_and_record`].
pub fn start_figures(board: &mut Board<PhysicsTransport>, pose_every: usize) -> Result<()> {
    let servos = board.transport_mut().robot_mut().servos_mut();
    servos.reset_figures();
    servos.start_log(pose_every);
    Ok(())
}

/// Walks `table` (slot 0) forward for `steps` steps at its planned period on `robot` (start its
/// log first if the log is wanted) for a fixed span, the `steps` periods and 3 more (the start
/// ramp, standing still after), looking at it every bus cycle: [`walk_and_record`] with
/// [`End::Limit`]. `each_cycle` sees the robot after every bus cycle. `what` names the walk in its
/// errors.
pub fn walk_forward(
    robot: PhysicsRobot,
    table: &[u8],
    steps: u32,
    what: &str,
    before_play: impl FnOnce(&mut Board<PhysicsTransport>) -> Result<()>,
    mut each_cycle: impl FnMut(&PhysicsRobot),
) -> Result<BodyWalk> {
    let period_s = f64::from(protocol::GaitTable::parse(table)?.header().step_period_us) * 1e-6;
    let walk = Walk {
        tables: vec![(0, table)],
        play: PlayCommand::forward(0, Steps::Count(steps)),
        queue: Vec::new(),
        what: what.to_owned(),
    };
    let follow = Follow {
        every: POLL,
        limit_s: (f64::from(steps) + 3.0) * period_s,
        end: End::Limit,
    };
    walk_and_record(robot, &walk, follow, before_play, |b, _| {
        each_cycle(b.transport().robot().servos());
        Ok(())
    })
}

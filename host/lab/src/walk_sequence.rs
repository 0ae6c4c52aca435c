//! A walk of several gaits as one run on the physics robot: e.g. straight, a curve, backward and
//! stop. Each distinct plan goes into its own slot, the first plays from standing and the others
//! are queued (`Board::queue_gait`, switched by the board at a step boundary without standing
//! still); the run's heading change, measured from the thorax, is set against the plans'.

use std::time::Duration;

use physics::{Figures, PhysicsRobot};
use planner::gait::{StepParams, Turn};
use planner::model::Model;
use protocol::{Direction, PlayCommand, RunState, Steps};

use crate::error::{Context, Result};
use crate::physics_walk::{BodyWalk, Follow, Walk, start_figures, walk_and_record};
use crate::walk_turn::{PlannedTurn, boundary_poses, heading_change, walk_table};

/// One part of a run: a plan's gait played `steps` steps in `direction`.
#[derive(Debug, Clone, PartialEq)]
pub struct Segment {
    pub params: StepParams,
    pub direction: Direction,
    pub steps: u32,
}

impl Segment {
    /// `params`' gait played `steps` steps in `direction`.
    pub fn new(params: &StepParams, direction: Direction, steps: u32) -> Self {
        Self {
            params: params.clone(),
            direction,
            steps,
        }
    }
}

/// Issue 28's run: `straight` for 2 steps, the same gait turned 6 deg per step to the left for
/// 15 steps (90 deg), `straight` backward for 2 steps, then stop, as one run of queued gaits.
/// Returns the walk and the turn's parameters.
pub fn ninety_degree_run(
    model: &Model,
    straight: &StepParams,
) -> Result<(SequenceWalk, StepParams)> {
    let mut turn = straight.clone();
    Turn {
        turn_deg: Some(6.0),
        radius_m: None,
    }
    .apply(&mut turn)
    .context("the turn of the 90 deg run")?;
    let walk = walk_sequence(
        model,
        &[
            Segment::new(straight, Direction::Forward, 2),
            Segment::new(&turn, Direction::Forward, 15),
            Segment::new(straight, Direction::Backward, 2),
        ],
    )?;
    Ok((walk, turn))
}

/// What one segment turned.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SegmentTurn {
    /// The plan's heading change over the segment, rad (backward walking turns the other way).
    pub planned_rad: f64,
    /// The thorax's yaw change between the segment's first and last step boundary, rad.
    pub measured_rad: f64,
}

/// A run of segments on the physics robot.
#[derive(Debug, Clone)]
pub struct SequenceWalk {
    /// The plans' heading change over the run, rad.
    pub planned_heading_rad: f64,
    /// The thorax's yaw change from standing before the run to standing after it, rad.
    pub measured_heading_rad: f64,
    pub segments: Vec<SegmentTurn>,
    /// The slots and directions the board played, in order, as its status showed them.
    pub played: Vec<(u8, Direction)>,
    /// Whether the board ramped (or stood) again between its first step and its last.
    pub stood_between: bool,
    /// Steps the board completed.
    pub steps: u32,
    /// What the run did to the body.
    pub figures: Figures,
}

/// How often the run is looked at, simulated time.
const POLL: Duration = Duration::from_millis(100);

/// Walks `segments` (at most 1 + the board's queue of 4; one slot per distinct plan) as one run on
/// a fresh physics robot on flat ground ([`walk_and_record`]), polling the board's status every
/// 100 ms.
pub fn walk_sequence(model: &Model, segments: &[Segment]) -> Result<SequenceWalk> {
    let Some((first, rest)) = segments.split_first() else {
        crate::bail!("no segments: give at least one gait to walk");
    };
    if let Some(s) = segments.iter().find(|s| s.steps == 0) {
        crate::bail!(
            "a segment of 0 steps ({} deg per step): give each at least one step",
            s.params.turn_per_step_rad().to_degrees()
        );
    }
    // One slot per distinct plan, in order of first use.
    let mut plans: Vec<(StepParams, PlannedTurn)> = Vec::new();
    let mut tables: Vec<Vec<u8>> = Vec::new();
    let mut slots = Vec::new();
    for s in segments {
        let slot = match plans.iter().position(|(p, _)| *p == s.params) {
            Some(i) => i,
            None => {
                if plans.len() == protocol::MAX_SLOTS {
                    crate::bail!("more than {} distinct plans", protocol::MAX_SLOTS);
                }
                let plan = planner::plan::plan(model, &s.params).with_context(|| {
                    format!("planning segment {} of {}", slots.len() + 1, model.name)
                })?;
                tables.push(
                    walk_table(&plan, &format!("seq{}", plans.len()))?
                        .bytes()
                        .to_vec(),
                );
                plans.push((s.params.clone(), PlannedTurn::of(&plan)));
                plans.len() - 1
            }
        };
        slots.push(slot as u8);
    }
    let command = |s: &Segment, slot: u8| {
        PlayCommand::new(
            slot,
            s.direction,
            protocol::units::PERIOD_SCALE_ONE,
            Steps::Count(s.steps),
        )
    };
    let walk = Walk {
        tables: tables
            .iter()
            .enumerate()
            .map(|(slot, t)| (slot as u8, t.as_slice()))
            .collect(),
        play: command(first, slots[0]),
        queue: rest
            .iter()
            .zip(&slots[1..])
            .map(|(s, &slot)| command(s, slot))
            .collect(),
        what: format!("the run of {} segments", segments.len()),
    };
    let walk_s: f64 = segments
        .iter()
        .map(|s| f64::from(s.steps) * s.params.period_s())
        .sum();
    let robot = PhysicsRobot::new(model, &planner::terrain::Ground::Flat)?;
    let (mut played, mut stood_between) = (Vec::new(), false);
    let BodyWalk { figures, log } = walk_and_record(
        robot,
        &walk,
        Follow::generous(POLL, walk_s),
        |b| start_figures(b, usize::MAX),
        |_, st| {
            if let Some(p) = st.playback
                && played.last() != Some(&(p.slot, p.direction))
            {
                played.push((p.slot, p.direction));
            }
            // Between the first step and the last the board only walks (or stops at the end,
            // standing with no playback).
            let standing_between = st.state == RunState::Standing && st.playback.is_some();
            if !played.is_empty() && (st.state == RunState::Ramping || standing_between) {
                stood_between = true;
            }
            Ok(())
        },
    )?;
    let total: u32 = segments.iter().map(|s| s.steps).sum();
    let poses = boundary_poses(&log, 0, total)
        .with_context(|| format!("the run's log lacks step boundaries 0 to {total}"))?;
    let mut turns = Vec::new();
    let mut at = 0usize;
    for (s, &slot) in segments.iter().zip(&slots) {
        let sign = match s.direction {
            Direction::Forward => 1.0,
            Direction::Backward => -1.0,
        };
        let end = at + s.steps as usize;
        turns.push(SegmentTurn {
            planned_rad: sign * plans[slot as usize].1.turn_per_step_rad * f64::from(s.steps),
            measured_rad: poses[end][2] - poses[at][2],
        });
        at = end;
    }
    Ok(SequenceWalk {
        planned_heading_rad: turns.iter().map(|t| t.planned_rad).sum(),
        measured_heading_rad: heading_change(&log),
        segments: turns,
        played,
        stood_between,
        steps: total,
        figures,
    })
}

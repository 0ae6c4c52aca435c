//! The one door by which the lab's own walks on simulated robots (the physics robot, the
//! virtual robot of `dbot demo`) reach the board library's upload: the table is checked by the
//! same rules as every other table (`board::rules::build::table_bytes`: slot capacity, the P gain
//! each joint's stiffness needs), with the servo-feasibility override given explicitly, because
//! these walks reproduce the paper's own gaits (table 1's 0.5 s swing is faster than an MX servo
//! follows) on a simulation, to show what they do. The override travels in the checked table.

use board::rules::Overrides;
use board::rules::build::CheckedTable;

use crate::{Context, Result};

/// `table` (named `what` in messages) checked for a walk on a simulated robot.
pub fn checked(table: &[u8], what: &str) -> Result<CheckedTable> {
    let (model, overrides) = rules()?;
    board::rules::build::table_bytes(table.to_vec(), what, &model, overrides)
        .with_context(|| format!("{what}: the step table"))
}

/// The model and the override every simulated walk's rules are checked with.
fn rules() -> Result<(planner::model::Model, Overrides)> {
    let model = planner::model::builtin("drosophibot2")?;
    Ok((
        model,
        Overrides {
            allow_infeasible: true,
        },
    ))
}

/// Plays `command` on a simulated robot under the period rule (with the override of
/// [`checked`]); `table` is the one the lab uploaded into its slot.
pub fn play<T: board::link::Transport>(
    board: &mut board::link::Board<T>,
    command: protocol::PlayCommand,
    table: Option<&CheckedTable>,
) -> Result<()> {
    let (model, overrides) = rules()?;
    let known = table.map(CheckedTable::bytes);
    let play = board::rules::period::check_play(board, command, known, &model, overrides)?;
    board.play(&play)?;
    Ok(())
}

/// Queues `command` after the gait playing on a simulated robot, under the period rule as
/// [`play`] plays.
pub fn queue<T: board::link::Transport>(
    board: &mut board::link::Board<T>,
    command: protocol::QueueCommand,
    table: Option<&CheckedTable>,
) -> Result<()> {
    let (model, overrides) = rules()?;
    let known = table.map(CheckedTable::bytes);
    let queued = board::rules::period::check_queue(board, command, known, &model, overrides)?;
    board.queue_gait(&queued)?;
    Ok(())
}

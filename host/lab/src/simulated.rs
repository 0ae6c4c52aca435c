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
    let model = planner::model::builtin("drosophibot2")?;
    board::rules::build::table_bytes(
        table.to_vec(),
        what,
        &model,
        Overrides {
            allow_infeasible: true,
        },
    )
    .with_context(|| format!("{what}: the step table"))
}

/// Plays `command` on a simulated robot under the period rule (with the override of
/// [`checked`]); `table` is the one the lab uploaded into its slot.
pub fn play<T: board::link::Transport>(
    board: &mut board::link::Board<T>,
    command: protocol::PlayCommand,
    table: Option<&CheckedTable>,
) -> Result<()> {
    let model = planner::model::builtin("drosophibot2")?;
    let overrides = Overrides {
        allow_infeasible: true,
    };
    let play = board::rules::period::check_play(
        board,
        command,
        table.map(CheckedTable::bytes),
        &model,
        overrides,
    )?;
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
    let model = planner::model::builtin("drosophibot2")?;
    let overrides = Overrides {
        allow_infeasible: true,
    };
    let queued = board::rules::period::check_queue(
        board,
        command,
        table.map(CheckedTable::bytes),
        &model,
        overrides,
    )?;
    board.queue_gait(&queued)?;
    Ok(())
}

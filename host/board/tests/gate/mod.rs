//! The tests' way through the rules to a board (`board::rules`): the link uploads, plays and
//! queues only what the rules made, so a test that drives a robot with a synthetic or paper
//! table checks it as every door does, with the servo-feasibility override given (the tests'
//! tables are not all ones an MX servo follows; what they test is the board). Shared by the test
//! crates of board, physics, lab and dbot (`#[path]`).
#![allow(dead_code)]

use board::link::{Board, LinkError, Transport, Uploaded};
use board::rules::Overrides;
use board::rules::build::CheckedTable;
use protocol::{PlayCommand, QueueCommand};

const ALLOW: Overrides = Overrides {
    allow_infeasible: true,
};

fn model() -> planner::model::Model {
    planner::model::builtin("drosophibot2").expect("the built-in model")
}

/// `bytes` checked by the rules (feasibility overridden).
pub fn table(bytes: &[u8]) -> CheckedTable {
    board::rules::build::table_bytes(bytes.to_vec(), "test table", &model(), ALLOW)
        .expect("a table the rules take")
}

/// Uploads `bytes` into `slot` through the rules.
pub fn upload<T: Transport>(b: &mut Board<T>, slot: u8, bytes: &[u8]) -> Uploaded {
    b.upload(slot, &table(bytes), |_, _| {})
}

/// Plays `command` through the period rule (feasibility overridden).
pub fn play<T: Transport>(b: &mut Board<T>, command: PlayCommand) -> Result<(), LinkError> {
    let checked = board::rules::period::check_play(b, command, None, &model(), ALLOW)
        .expect("the period rule");
    b.play(&checked)
}

/// Queues `command` through the period rule (feasibility overridden).
pub fn queue<T: Transport>(b: &mut Board<T>, command: QueueCommand) -> Result<(), LinkError> {
    let checked = board::rules::period::check_queue(b, command, None, &model(), ALLOW)
        .expect("the period rule");
    b.queue_gait(&checked)
}

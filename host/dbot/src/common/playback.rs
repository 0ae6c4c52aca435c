//! Stopping playback on Ctrl-C, for `dbot run`. Starting it (the table to upload first, the play
//! command and its announcement) is the lab's, `lab::trial_record::playback`, shared with
//! `dbot record` and Python.

use anyhow::Context;
use board::link::{Board, Transport};
use board::record::Stopped;

/// Asks the board to stop the walk (the one stop path, `board::record::stop_walk`) and says
/// what it did.
pub fn stop_walk<T: Transport>(board: &mut Board<T>) -> anyhow::Result<Stopped> {
    board::record::stop_walk(board).context("stopping the walk after Ctrl-C")
}

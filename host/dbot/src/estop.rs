//! `dbot estop`: torque off on every servo at once, from any state. `dbot status` shows the fault;
//! `dbot set --clear-fault` leaves it.

use crate::args::board::BoardArgs;

/// Runs the command on the board `board` names.
pub fn run(board: BoardArgs) -> anyhow::Result<()> {
    let mut s = board.connect()?;
    s.board.emergency_stop()?;
    let st = s.board.status()?;
    let fault = st
        .fault
        .map_or("no fault recorded".to_owned(), |f| f.to_string());
    // The virtual robot boots afresh at the next command, so there is no fault left to clear.
    let next = if s.is_virtual() {
        "the virtual robot starts afresh (idle, torque off) at the next command"
    } else {
        "clear it with `dbot set --clear-fault`"
    };
    println!(
        "emergency stop: the board is in state {} ({fault}); {next}",
        st.state.name()
    );
    s.close()
}

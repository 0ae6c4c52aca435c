//! `dbot stop`: ends walking at the end of the current step (never mid-swing).

use board::link::LinkError;
use protocol::{ProtocolError, RunState};

use crate::args::board::BoardArgs;

/// Runs the command on the board `board` names.
pub fn run(board: BoardArgs) -> anyhow::Result<()> {
    let mut s = board.connect()?;
    match s.board.stop() {
        Ok(()) => {
            let st = s.board.status()?;
            // The board acknowledges Stop in Idle and Standing too: nothing was moving.
            let verdict = match st.state {
                RunState::Idle | RunState::Standing => "nothing to stop",
                _ => "stop accepted",
            };
            println!("{verdict}: the board is in state {}", st.state.name());
        }
        // Stopping a robot that is not walking is not an error for the person asking.
        Err(LinkError::Device {
            error: ProtocolError::WrongState { state },
            ..
        }) => println!("nothing to stop: the board is in state {}", state.name()),
        Err(LinkError::Faulted { fault, .. }) => println!(
            "nothing to stop: the board is in a fault ({})",
            fault.map_or_else(|| "fault unknown".to_owned(), |f| f.to_string())
        ),
        Err(e) => return Err(e.into()),
    }
    s.close()
}

//! `dbot estop`: torque off on every servo at once, from any state. `dbot status` shows the fault;
//! `dbot set --clear-fault` leaves it.

use crate::args::board::BoardArgs;

/// Emergency stop: torque off on every servo now (the robot goes limp).
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub board: BoardArgs,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        let mut s = self.board.connect()?;
        s.board.emergency_stop()?;
        let st = s.board.status()?;
        println!(
            "emergency stop: the board is {:?} (fault {:?}); clear it with `dbot set --clear-fault`",
            st.state, st.fault
        );
        s.close()
    }
}

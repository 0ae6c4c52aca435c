//! An open board and the setup it was opened with (`BoardArgs::connect` opens one).

use anyhow::Context;
use board::link::Transport;
use physics::{Robot, RobotLink};

use board::setup_file::RobotConfig;

/// An open board and the setup it was opened with.
#[derive(Debug)]
pub struct Session {
    /// The robot; its link says which kind it is.
    pub board: Robot,
    pub setup: RobotConfig,
    /// The store file of a `virtual:PATH` robot (its settings are kept beside it).
    pub store: Option<std::path::PathBuf>,
}

impl Session {
    /// Whether the board is the in-process virtual robot (it lives only as long as this process).
    pub fn is_virtual(&self) -> bool {
        match self.board.transport() {
            RobotLink::Virtual(_) => true,
            RobotLink::Serial(_) | RobotLink::Physics(_) => false,
        }
    }

    /// Ends the session (the virtual robot writes its flash image).
    pub fn close(mut self) -> anyhow::Result<()> {
        let port = self.board.port().to_owned();
        self.board
            .transport_mut()
            .shutdown()
            .with_context(|| format!("closing {port}"))
    }
}

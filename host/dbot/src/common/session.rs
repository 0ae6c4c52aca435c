//! An open board and the setup it was opened with (`BoardArgs::connect` opens one).

use anyhow::Context;
use board::link::{Board, Transport};
use board::port::PortSpec;

use crate::config::RobotConfig;

/// An open board and the setup it was opened with.
#[derive(Debug)]
pub struct Session {
    pub board: Board<Box<dyn Transport>>,
    pub setup: RobotConfig,
    /// The store file of a `virtual:PATH` robot (its settings are kept beside it).
    pub store: Option<std::path::PathBuf>,
}

impl Session {
    /// Whether the board is the in-process virtual robot (it lives only as long as this process).
    pub fn is_virtual(&self) -> bool {
        matches!(PortSpec::parse(self.board.port()), PortSpec::Virtual { .. })
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

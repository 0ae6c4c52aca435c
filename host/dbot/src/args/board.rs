//! The options every board command shares (`--port`, `--config`) and the session they open.

use std::path::PathBuf;

use crate::common::session::Session;
use crate::config::RobotConfig;
use anyhow::{Context, bail};
use board::link::{Board, list_boards};
use board::port::PortSpec;

/// Where the default virtual robot keeps its flash between commands.
pub const DEFAULT_IMAGE: &str = "out/virtual-robot.flash";

/// Which board to talk to.
#[derive(Debug, Clone, clap::Args)]
pub struct BoardArgs {
    /// Board port: a serial device (/dev/ttyACM0, or a pseudo-terminal such as the emulator's
    /// bridge), `virtual` (an in-process virtual robot with an erased flash), or `virtual:PATH`
    /// (one whose flash is kept in the file PATH between commands). Default: the setup file's port,
    /// else the one board plugged in, else `virtual:out/virtual-robot.flash`.
    #[arg(long, short = 'p', global = true)]
    pub port: Option<String>,
    /// Robot setup file (TOML). Default: $DBOT_CONFIG, ./dbot.toml, ~/.config/dbot/config.toml.
    #[arg(long, global = true)]
    pub config: Option<PathBuf>,
}

impl BoardArgs {
    /// The setup file (or an empty setup).
    pub fn setup(&self) -> anyhow::Result<RobotConfig> {
        Ok(RobotConfig::find(self.config.as_deref())?.0)
    }

    /// The port to use: flag, setup file, the single board plugged in, the default virtual robot.
    pub fn port(&self, setup: &RobotConfig) -> anyhow::Result<String> {
        if let Some(p) = self.port.clone().or_else(|| setup.port.clone()) {
            return Ok(p);
        }
        let boards = list_boards().unwrap_or_default();
        match boards.as_slice() {
            [one] => Ok(one.path.clone()),
            [] => {
                eprintln!(
                    "no board plugged in: using the virtual robot (flash kept in {DEFAULT_IMAGE})"
                );
                Ok(format!("virtual:{DEFAULT_IMAGE}"))
            }
            many => bail!(
                "{} boards are plugged in ({}): choose one with --port",
                many.len(),
                many.iter()
                    .map(|b| b.path.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        }
    }

    /// Opens the port and connects (checking the protocol and table format versions).
    pub fn connect(&self) -> anyhow::Result<Session> {
        let setup = self.setup()?;
        let port = self.port(&setup)?;
        let transport = PortSpec::parse(&port).open()?;
        let board = Board::connect(transport).with_context(|| format!("connecting to {port}"))?;
        Ok(Session { board, setup })
    }
}

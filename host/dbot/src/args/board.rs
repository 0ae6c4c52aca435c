//! The options every board command shares (`--port`, `--config`) and the session they open, and
//! the gait slot of the commands that fill or play one (`--slot`, `--allow-infeasible`).

use std::path::PathBuf;

use crate::common::session::Session;
use anyhow::{Context, bail};
use board::link::list_boards;
use board::port::PortSpec;
use board::setup_file::RobotConfig;

/// Where the default virtual robot keeps its flash between commands.
pub const DEFAULT_IMAGE: &str = "out/virtual-robot.flash";

/// Which board to talk to.
#[derive(Debug, Clone, clap::Args)]
pub struct BoardArgs {
    /// Board port: a serial device (/dev/ttyACM0, or a pseudo-terminal such as the emulator's
    /// bridge), `virtual` (an in-process virtual robot with an erased flash), `virtual:PATH`
    /// (one whose flash, and what `dbot set` set, is kept beside the file PATH between commands),
    /// or `physics[:SCENE]` (the virtual robot with a MuJoCo body; scenes flat, incline:DEG, ball,
    /// ball-fixed). Default: the setup file's port, else the one board plugged in, else
    /// `virtual:out/virtual-robot.flash`.
    #[arg(long, short = 'p', global = true)]
    pub port: Option<String>,
    /// Robot setup file (TOML). Default: $DBOT_CONFIG, ./dbot.toml, ~/.config/dbot/config.toml.
    #[arg(long, global = true)]
    pub config: Option<PathBuf>,
    /// Start a new, empty virtual robot if the `virtual:PATH` store does not exist yet (without
    /// it a missing store is an error, so that a mistyped path is not a silent new robot).
    #[arg(long, global = true)]
    pub create: bool,
}

/// The gait slot of a command that fills or plays one (`upload`, `run`), and the override of the
/// servo-feasibility rule for the gait that goes into it or plays from it.
#[derive(Debug, Clone, clap::Args)]
pub struct GaitSlotArgs {
    /// Gait slot (default: the setup file's slot, else 0).
    #[arg(long)]
    pub slot: Option<u8>,
    #[command(flatten)]
    pub feasibility: crate::feasibility_args::FeasibilityArgs,
}

impl GaitSlotArgs {
    /// The flag's slot, else the setup file's, else 0.
    pub fn slot(&self, setup: &RobotConfig) -> u8 {
        self.slot.or(setup.slot).unwrap_or(0)
    }
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
        let spec = PortSpec::parse(&port)?;
        // The fallback robot is dbot's own choice, not a path anyone typed: it is created freely.
        let chosen = self.port.is_some() || setup.port.is_some();
        if let PortSpec::Virtual { image: Some(path) } = &spec {
            if chosen {
                check_store_exists(path, self.port.is_some(), self.create)?;
            } else if let Some(dir) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
                // Its folder too (`out/` in a fresh folder): the store's lock file lives there.
                std::fs::create_dir_all(dir)
                    .with_context(|| format!("creating {} for the virtual robot", dir.display()))?;
            }
        }
        // The library applies what `dbot set` saved beside a `virtual:PATH` store.
        let board = physics::open(&port).with_context(|| format!("connecting to {port}"))?;
        let store = spec.store().map(std::path::Path::to_owned);
        Ok(Session {
            board,
            setup,
            store,
        })
    }
}

/// A typed `virtual:PATH` must name an existing store unless `--create` is given, and its folder
/// must exist even then (`--create` makes a robot, not a folder tree from a typo).
pub(crate) fn check_store_exists(
    path: &std::path::Path,
    from_flag: bool,
    create: bool,
) -> anyhow::Result<()> {
    if path.exists() {
        return Ok(());
    }
    let source = if from_flag {
        "--port"
    } else {
        "the setup file's port"
    };
    let parent = path.parent().filter(|p| !p.as_os_str().is_empty());
    if let Some(dir) = parent
        && !dir.is_dir()
    {
        bail!(
            "virtual robot store {}: no such folder {} (from {source}; mistyped?)",
            path.display(),
            dir.display()
        );
    }
    if create {
        return Ok(());
    }
    bail!(
        "virtual robot store {} does not exist (from {source}): mistyped? Give --create to start a new, empty robot there",
        path.display()
    )
}

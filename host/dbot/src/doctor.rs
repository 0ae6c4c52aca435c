//! `dbot doctor`: the bring-up check of a freshly wired robot. The checks are `lab::doctor`
//! (Python's `dbot.doctor()` runs the same); this file parses and prints.

use anyhow::bail;

use board::port::PortSpec;

use crate::args::board::{BoardArgs, check_store_exists};
use crate::common::model_spec::load_model;

/// Check a freshly wired robot: the board, every servo of the model file, the supply, the strain board.
///
/// Prints one line per item, PASS or FAIL with what to do, in the order to fix them (the board,
/// then the servos on the bus, the supply voltage read from the servos, the strain board), and
/// exits non-zero if anything failed. The servos' registers are read on the servo bus: with
/// `--bus`, a U2D2 on the robot's bus (unplug the board's bus cable) or `dbot sim-bus`'s link;
/// for the virtual and physics robots, their own simulated bus. The board's protocol carries no
/// register reads, so for a board without `--bus` the servos are not checked.
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot doctor --port virtual --strain virtual       # the virtual robot and a virtual strain board
  dbot doctor --port physics                        # the physics robot
  dbot doctor --bus /dev/ttyUSB0 --baud 1000000     # [needs servos] the servos through a U2D2
  dbot doctor --port /dev/ttyACM0 --strain /dev/ttyACM1  # [needs a board] board and strain board")]
pub struct Args {
    /// The model whose servos must answer: a built-in name, a .toml or an .aproj file
    #[arg(long, default_value = "drosophibot2")]
    model: String,
    /// Servo bus on a serial port: a U2D2 on the robot's bus, or the --link of `dbot sim-bus`
    #[arg(long)]
    bus: Option<String>,
    /// Rate the servos must answer at, bit/s (default: the board's bus rate, else 1000000)
    #[arg(long)]
    baud: Option<u32>,
    /// The strain board's port (`virtual`, or a serial device); default: not checked
    #[arg(long)]
    strain: Option<String>,
    /// Seconds of strain samples to read after calibration
    #[arg(long, default_value_t = 2.0)]
    strain_seconds: f64,
    #[command(flatten)]
    board: BoardArgs,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        let model = load_model(&self.model)?;
        // With only a servo bus named, no board is looked for.
        let port = match (&self.board.port, &self.bus) {
            (None, Some(_)) => None,
            _ => {
                let setup = self.board.setup()?;
                let port = self.board.port(&setup)?;
                // A typed `virtual:PATH` must exist, as for every board command.
                if let PortSpec::Virtual { image: Some(path) } = PortSpec::parse(&port)?
                    && (self.board.port.is_some() || setup.port.is_some())
                {
                    check_store_exists(&path, self.board.port.is_some(), self.board.create)?;
                }
                Some(port)
            }
        };
        let options = lab::doctor::Options {
            port,
            bus: self.bus,
            baud: self.baud,
            strain: self.strain,
            strain_seconds: self.strain_seconds,
        };
        let report = lab::doctor::run(&model, &options);
        print!("{}", report.text());
        if !report.ok() {
            bail!("the robot is not ready: fix the FAIL items above, first one first");
        }
        Ok(())
    }
}

//! `dbot`: plan gaits for Drosophibot II, build step tables, drive the board and record what it did.
//!
//! One file per subcommand; each holds a clap `Args` struct whose doc comments are the help text,
//! and a `run(self)` that does the work.

mod dxl;
mod sim_bus;

use clap::{Parser, Subcommand};

/// Plan, run and record gaits of the Drosophibot II hexapod.
///
/// Units on the command line are SI (m, s, rad, N m) unless a flag says otherwise.
#[derive(Debug, Parser)]
#[command(name = "dbot", version, about, long_about)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Debug, Subcommand)]
enum Cmd {
    /// Serve virtual Dynamixel servos on a pseudo-terminal
    SimBus(sim_bus::Args),
    /// Set up and inspect Dynamixel servos through a USB serial adapter
    Dxl(dxl::Args),
}

fn main() -> anyhow::Result<()> {
    let cli = Cli::parse();
    match cli.cmd {
        Cmd::SimBus(a) => a.run(),
        Cmd::Dxl(a) => a.run(),
    }
}

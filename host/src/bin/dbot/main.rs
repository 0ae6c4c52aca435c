//! `dbot`: plan gaits for Drosophibot II, build step tables, drive the board and record what it did.
//!
//! One file per subcommand; each holds a clap `Args` struct whose doc comments are the help text,
//! and a `run(self)` that does the work.

use clap::{Parser, Subcommand};

mod model;
mod plan;
mod board_args;
mod devices;
mod estop;
mod gaits;
mod record;
mod run;
mod servos;
mod set;
mod status;
mod stop;
mod upload;

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
    /// Plan a step cycle (posture, footpaths, inverse kinematics) and write CSV, JSON, URDF, plots.
    Plan(plan::Args),
    /// Export, import or inspect organism models.
    Model(model::Args),
    /// List the boards plugged in over USB.
    Devices(devices::Args),
    /// Upload a step table into a gait slot.
    Upload(upload::Args),
    /// List the board's gait slots.
    Gaits(gaits::Args),
    /// Play a gait.
    Run(run::Args),
    /// Stop walking at the end of the step.
    Stop(stop::Args),
    /// Emergency stop: torque off everywhere.
    Estop(estop::Args),
    /// Show the board's state and counters.
    Status(status::Args),
    /// Show the joints and their servos.
    Servos(servos::Args),
    /// Change run-time settings (stiffness, rate, baud).
    Set(set::Args),
    /// Record telemetry to CSV and plot it.
    Record(record::Args),
}

fn main() -> anyhow::Result<()> {
    let cli = Cli::parse();
    match cli.cmd {
        Cmd::Plan(a) => a.run(),
        Cmd::Model(a) => a.run(),
        Cmd::Devices(a) => a.run(),
        Cmd::Upload(a) => a.run(),
        Cmd::Gaits(a) => a.run(),
        Cmd::Run(a) => a.run(),
        Cmd::Stop(a) => a.run(),
        Cmd::Estop(a) => a.run(),
        Cmd::Status(a) => a.run(),
        Cmd::Servos(a) => a.run(),
        Cmd::Set(a) => a.run(),
        Cmd::Record(a) => a.run(),
    }
}

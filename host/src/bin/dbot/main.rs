//! `dbot`: plan gaits for Drosophibot II, build step tables, drive the board and record what it did.
//!
//! One file per subcommand; each holds a clap `Args` struct whose doc comments are the help text,
//! and a `run(self)` that does the work.

mod board_args;
mod compare;
mod demo;
mod devices;
mod dxl;
mod dynamics_args;
mod estop;
mod gaits;
mod interrupt;
mod model;
mod plan;
mod record;
mod run;
mod servos;
mod set;
mod sim_bus;
mod status;
mod stop;
mod table;
mod upload;

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
    /// Plan, upload, walk and record Drosophibot II's tripod gait on the virtual robot.
    Demo(demo::Args),
    /// Plan a step cycle (posture, footpaths, inverse kinematics) and write CSV, JSON, URDF, plots.
    Plan(plan::Args),
    /// Export, import or inspect organism models.
    Model(model::Args),
    /// Build the board's step table from a plan directory.
    Table(table::Args),
    /// Compare two plans DoF by DoF (R-squared of angles and torques), or sweep swing durations.
    Compare(compare::Args),
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
    /// Serve virtual Dynamixel servos on a pseudo-terminal.
    SimBus(sim_bus::Args),
    /// Set up and inspect Dynamixel servos through a USB serial adapter.
    Dxl(dxl::Args),
}

fn main() -> anyhow::Result<()> {
    // `dbot gaits | head -1`: end quietly when the reader goes away, as Unix tools do, instead of
    // panicking in `println!` (Rust ignores SIGPIPE by default).
    // SAFETY: restoring a signal's default action before any thread starts.
    unsafe { nix::libc::signal(nix::libc::SIGPIPE, nix::libc::SIG_DFL) };
    let cli = Cli::parse();
    match cli.cmd {
        Cmd::Demo(a) => a.run(),
        Cmd::Plan(a) => a.run(),
        Cmd::Model(a) => a.run(),
        Cmd::Table(a) => a.run(),
        Cmd::Compare(a) => a.run(),
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
        Cmd::SimBus(a) => a.run(),
        Cmd::Dxl(a) => a.run(),
    }
}

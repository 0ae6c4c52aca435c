//! `dbot`: plan gaits for Drosophibot II, build step tables, drive the board and record what it did.
//!
//! One file per subcommand; each holds a clap `Args` struct whose doc comments are the help text,
//! and a `run(self)` that does the work (`gaits`, `stop`, `estop` and `status` take only the board's
//! flags: their `run(board)` takes those, and their help text is on their variant below).

mod args;
mod calibrate;
mod common;
mod compare;
mod demo;
mod devices;
mod doctor;
mod dxl;
mod estop;
mod excite;
mod feasibility_args;
mod gaits;
mod identify;
mod model;
mod paper_robot;
mod plan;
mod record;
mod replay;
mod run;
mod servos;
mod set;
mod sim_bus;
mod sim_strain;
mod spring_args;
mod status;
mod steer;
mod stop;
mod strain;
mod table;
mod upload;
mod validate;

use clap::{Parser, Subcommand};

use crate::args::board::BoardArgs;

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
    // No doc comments on a variant with its own `Args`: clap takes that subcommand's help (short
    // and long) from the struct's doc comment, which a comment on the variant would replace. The
    // commands that take nothing but the board carry their help here.
    Demo(demo::Args),
    PaperRobot(paper_robot::Args),
    Plan(plan::Args),
    Model(model::Args),
    Table(table::Args),
    Excite(excite::Args),
    Identify(identify::Args),
    Replay(replay::Args),
    Calibrate(calibrate::Args),
    Compare(compare::Args),
    Devices(devices::Args),
    Upload(upload::Args),
    /// List the board's gait slots.
    #[command(after_help = "Examples:
  dbot gaits
  dbot gaits --port virtual:lab.flash")]
    Gaits(BoardArgs),
    Run(run::Args),
    /// Stop walking at the end of the current step.
    #[command(after_help = "Example:
  dbot stop")]
    Stop(BoardArgs),
    Steer(steer::Args),
    /// Emergency stop: torque off on every servo now (the robot goes limp).
    #[command(after_help = "Example:
  dbot estop                     # then: dbot set --clear-fault")]
    Estop(BoardArgs),
    /// Show the board's state and counters.
    #[command(after_help = "Examples:
  dbot status
  dbot status --port virtual:lab.flash")]
    Status(BoardArgs),
    Servos(servos::Args),
    Set(set::Args),
    Record(record::Args),
    SimBus(sim_bus::Args),
    SimStrain(sim_strain::Args),
    Strain(strain::Args),
    Dxl(dxl::Args),
    Doctor(doctor::Args),
    Validate(validate::Args),
}

fn main() -> std::process::ExitCode {
    // `dbot gaits | head -1`: end quietly when the reader goes away, as Unix tools do, instead of
    // panicking in `println!` (Rust ignores SIGPIPE by default).
    // SAFETY: restoring a signal's default action before any thread starts.
    unsafe { nix::libc::signal(nix::libc::SIGPIPE, nix::libc::SIG_DFL) };
    let cli = Cli::parse();
    let result = match cli.cmd {
        Cmd::Demo(a) => a.run(),
        Cmd::PaperRobot(a) => a.run(),
        Cmd::Plan(a) => a.run(),
        Cmd::Model(a) => a.run(),
        Cmd::Table(a) => a.run(),
        Cmd::Excite(a) => a.run(),
        Cmd::Identify(a) => a.run(),
        Cmd::Replay(a) => a.run(),
        Cmd::Calibrate(a) => a.run(),
        Cmd::Compare(a) => a.run(),
        Cmd::Devices(a) => a.run(),
        Cmd::Upload(a) => a.run(),
        Cmd::Gaits(board) => gaits::run(board),
        Cmd::Run(a) => a.run(),
        Cmd::Stop(board) => stop::run(board),
        Cmd::Steer(a) => a.run(),
        Cmd::Estop(board) => estop::run(board),
        Cmd::Status(board) => status::run(board),
        Cmd::Servos(a) => a.run(),
        Cmd::Set(a) => a.run(),
        Cmd::Record(a) => a.run(),
        Cmd::SimBus(a) => a.run(),
        Cmd::SimStrain(a) => a.run(),
        Cmd::Strain(a) => a.run(),
        Cmd::Dxl(a) => a.run(),
        Cmd::Doctor(a) => a.run(),
        Cmd::Validate(a) => a.run(),
    };
    // Each cause once: many library errors write their source into their own text.
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("{}", common::error_chain::report(&e));
            std::process::ExitCode::FAILURE
        }
    }
}

//! `dbot`: plan gaits for Drosophibot II, build step tables, drive the board and record what it did.
//!
//! One file per subcommand; each holds a clap `Args` struct whose doc comments are the help text,
//! and a `run(self)` that does the work.

use clap::{Parser, Subcommand};

mod compare;
mod dynamics_args;
mod model;
mod plan;
mod table;

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
    /// Compare two plans DoF by DoF (R-squared of angles and torques), or sweep swing durations.
    Compare(compare::Args),
    /// Build the board's step table from a plan directory.
    Table(table::Args),
}

fn main() -> anyhow::Result<()> {
    let cli = Cli::parse();
    match cli.cmd {
        Cmd::Plan(a) => a.run(),
        Cmd::Model(a) => a.run(),
        Cmd::Compare(a) => a.run(),
        Cmd::Table(a) => a.run(),
    }
}

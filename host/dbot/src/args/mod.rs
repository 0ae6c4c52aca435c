//! Argument groups that several subcommands flatten into their own `Args` (`#[command(flatten)]`):
//! how to reach a board, the model and setup file of planning, and the inverse-dynamics options.
//! Subcommands share these instead of importing each other.

pub mod board;
pub mod dynamics;
pub mod setup;

//! Helpers that several subcommands use: Ctrl-C handling, ... Subcommands share these instead of
//! importing each other.

pub mod interrupt;

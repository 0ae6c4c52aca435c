//! Helpers that several subcommands use (Ctrl-C handling, whole-file outputs, `--model` specs, the
//! gait summary line, the Dynamixel default baud, the
//! words for board states and for an error's chain of causes, starting and stopping playback,
//! what a gait slot lost, the words of the demo's walk figures).
//! Subcommands share these instead of importing each other; nothing here imports a subcommand.

pub mod baud;
pub mod error_chain;
pub mod interrupt;
pub mod model_spec;
pub mod output;
pub mod playback;
pub mod session;
pub mod words;

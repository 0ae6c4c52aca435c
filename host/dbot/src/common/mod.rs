//! Helpers that several subcommands use (Ctrl-C handling, whole-file outputs, `--model` specs, the
//! gait summary line, starting and stopping playback, the step table of a solved plan).
//! Subcommands share these instead of importing each other; nothing here imports a subcommand.

pub mod gait_summary;
pub mod interrupt;
pub mod model_spec;
pub mod output;
pub mod overlay;
pub mod playback;
pub mod step_table;

//! The integration tests of `report`, one module per topic, linked into one test binary (one link
//! instead of one per file; nextest still runs each test in its own process).

mod plot_legends;
mod plot_text;
mod recording_plots;
mod robot_blocks;
mod robot_drawing;
mod robot_walk;

//! The integration tests of `board`, one module per topic, linked into one test binary (one link
//! instead of one per file; nextest still runs each test in its own process).

mod bench_pty;
mod excitation_rules;
mod files_rules;
mod platform_link;
mod record_duration;
mod record_rate;
mod robot_chain;
mod robot_gait_switch;
mod robot_link;
mod robot_stuck;
mod rules;
mod servo_map;
mod stream_table;
mod telemetry_csv_cells;
mod trial_records;
mod walk_stop;

/// The tests' way through the rules to a board, shared with the other host crates' tests.
#[path = "../gate/mod.rs"]
mod gate;

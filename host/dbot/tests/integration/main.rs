//! The integration tests of `dbot`, one module per topic, linked into one test binary (one link
//! instead of one per file; nextest still runs each test in its own process).

// Helpers shared by several modules.
mod board_fakes;
mod cli_support;
#[path = "sdk/sim_bus.rs"]
mod sim_bus_support;

mod calibrate_cli;
mod cli_messages;
mod compare_trials;
mod demo_physics;
mod doc_examples;
mod docs_commands;
mod docs_transcript;
mod dxl_cli;
mod dxl_sdk;
mod figure_stamps;
mod identify_cli;
mod paper_robot;
mod plan_cli;
mod plan_cli_springs;
mod plan_cli_turn;
mod plan_csv_tidy;
mod plan_dir_roundtrip;
mod record_joint_map;
mod record_names;
mod record_perturb;
mod record_perturb_physics;
mod record_strain;
mod record_trials;
mod refusal_doors;
mod reliability_board_cli;
mod reliability_bounds;
mod reliability_cli;
mod reliability_limits;
mod reliability_stores;
mod robot_cli;
mod robot_demo;
mod robot_record;
mod run_then_cli;
mod sim_bus_physics;
mod steer_cli;
mod store_damage_cli;
mod strain_cli;
mod validation_doc;

/// The tests' way through the rules to a board, shared with the other host crates' tests.
#[path = "../../../board/tests/gate/mod.rs"]
pub mod gate;

//! The integration tests of `physics`, one module per topic, linked into one test binary (one link
//! instead of one per file; nextest still runs each test in its own process).

// Helpers shared by several modules.
mod servo_dynamics;
mod support;

mod blocks;
mod bus_traffic;
mod firmware_in_the_loop;
mod fly_timestep;
mod mjcf_model_data;
mod p_gain;
mod plant_state;
mod platform_servo;
mod ports;
mod set_stiffness;
mod standing;
mod strain_standing;
mod substrate;
mod walk_figures;
mod walk_log;

/// The tests' way through the rules to a board, shared with the other host crates' tests.
#[path = "../../../board/tests/gate/mod.rs"]
pub mod gate;

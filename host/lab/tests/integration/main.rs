//! The integration tests of `lab`, one module per topic, linked into one test binary (one link
//! instead of one per file; nextest still runs each test in its own process).

mod calibrate;
mod doctor;
mod identify;
mod identify_friction;
mod identify_refine;
mod perturbation;
mod physics_serve;
mod pinned_walk;
mod plan_dir_consistency;
mod steer_blend;
mod strain_gain;
mod strain_walking;
mod substrates;
mod trial_record;
mod walk_sequence;
mod walk_turn;

/// The tests' way through the rules to a board, shared with the other host crates' tests.
#[path = "../../../board/tests/gate/mod.rs"]
mod gate;

//! Planner parameter files and StepParams::validate: validated parameters give finite footpaths.
//! The property checked is `plan_params` in host/planner/tests/integration/reliability_common/mod.rs, shared with the
//! bounded proptest of the normal suite (host/planner/tests/integration/reliability_inputs.rs).
#![no_main]

#[path = "../../host/planner/tests/integration/reliability_common/mod.rs"]
mod checks;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = checks::plan_params(data);
});

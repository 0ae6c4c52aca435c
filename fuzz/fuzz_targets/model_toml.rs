//! Model TOML loader: any text loads or is an error; a loaded model writes TOML that loads again.
//! The property checked is `model_toml` in host/planner/tests/integration/reliability_common/mod.rs, shared with the
//! bounded proptest of the normal suite (host/planner/tests/integration/reliability_inputs.rs).
#![no_main]

#[path = "../../host/planner/tests/integration/reliability_common/mod.rs"]
mod checks;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = checks::model_toml(data);
});

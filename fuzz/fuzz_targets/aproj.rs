//! AnimatLab importer: any text imports or is an error; an imported model is a valid model file.
//! The property checked is `aproj` in host/planner/tests/integration/reliability_common/mod.rs, shared with the bounded
//! proptest of the normal suite (host/planner/tests/integration/reliability_inputs.rs).
#![no_main]

#[path = "../../host/planner/tests/integration/reliability_common/mod.rs"]
mod checks;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = checks::aproj(data);
});

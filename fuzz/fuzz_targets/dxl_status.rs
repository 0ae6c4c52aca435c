//! Dynamixel status parser: any bytes in any chunking give frames or rejected packets, never a
//! panic or a stall. The property checked is `dxl_status` in host/planner/tests/integration/reliability_common/mod.rs,
//! shared with the bounded proptest of the normal suite (host/planner/tests/integration/reliability_inputs.rs).
#![no_main]

#[path = "../../host/planner/tests/integration/reliability_common/mod.rs"]
mod checks;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = checks::dxl_status(data);
});

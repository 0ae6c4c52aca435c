//! The release image logs its state changes and faults with defmt (firmware/src/device_log.rs):
//! booted with 22 virtual servos, given a gait, walking, then a servo overload. The decoded RTT
//! lines must name each move through the state diagram of firmware/src/safety/mod.rs, in order,
//! with the faulted joint, its servo ID and the overload bit read back from the servo.

use anyhow::Result;
use hil_tests::drive::{start_playing, start_with_servos, upload_sine_gait};
use hil_tests::gait::JOINTS;
use hil_tests::state_log::{UPLOAD_AND_WALK, ensure_state_changes, state_lines};
use protocol::message::{Direction, Steps};
use serde_json::json;
use std::time::Duration;

const HIL_BUS: &str = env!("CARGO_BIN_EXE_hil-bus");

#[test]
fn state_changes_and_a_servo_fault_are_logged_over_defmt() -> Result<()> {
    let Some((board, mut link)) = start_with_servos("device_log", HIL_BUS, JOINTS, 1_000_000)?
    else {
        return Ok(());
    };
    let Some(emu) = board.emulator() else {
        return hil_tests::target::skip(
            "device_log",
            "injecting an overload needs the emulator's servo model",
        );
    };
    upload_sine_gait(&mut link, "device-log", None)?;
    start_playing(&mut link, 0, Direction::Forward, Steps::Continuous)?;
    let s = Duration::from_secs(5);
    board.wait_for_log("state Ramping -> Walking on Event(RampDone)", s)?;
    // Servo ID 3 is the table's third joint (index 2); the overload is bit 5 (32) of register 70.
    emu.bus_control(json!({"overload": 3}))?;
    let bits = "state Safe(ServoError { joint: 2, id: 3, error: 0 }) -> \
                Safe(ServoError { joint: 2, id: 3, error: 32 }) on ErrorBits";
    board.wait_for_log(bits, s)?;
    emu.run_for(Duration::from_millis(200))?;

    // The board walks from an empty store (see UPLOAD_AND_WALK); the overload stops it.
    let want = [
        &UPLOAD_AND_WALK[..],
        &[
            "state Walking -> Safe(ServoError { joint: 2, id: 3, error: 0 }) on \
             Event(Fault(ServoError { joint: 2, id: 3, error: 0 }))",
            bits,
        ],
    ]
    .concat();
    let lines = state_lines(emu);
    println!("{}", lines.join("\n"));
    ensure_state_changes(&lines, &want)?;
    Ok(())
}

//! The release image logs its state changes and faults with defmt (firmware/src/device_log.rs):
//! booted with 22 virtual servos, given a gait, walking, then a servo overload. The decoded RTT
//! lines must name each move through the state diagram of firmware/src/safety/mod.rs, in order,
//! with the faulted joint, its servo ID and the overload bit read back from the servo.

use anyhow::{Result, ensure};
use hil_tests::drive::{T, start_playing, start_with_servos};
use hil_tests::gait::{JOINTS, sine_gait, upload};
use protocol::message::{Direction, Steps};
use protocol::{MAX_CHUNK_LEN, Response};
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
    let (builder, table) = sine_gait("device-log", 40, 0.2)?;
    let r = upload(&mut link, 0, &builder, &table, MAX_CHUNK_LEN, T)?;
    ensure!(matches!(r, Response::Committed { .. }), "{r:?}");
    start_playing(&mut link, 0, Direction::Forward, Steps::Continuous)?;
    let s = Duration::from_secs(5);
    board.wait_for_log("state Ramping -> Walking on Event(RampDone)", s)?;
    // Servo ID 3 is the table's third joint (index 2); the overload is bit 5 (32) of register 70.
    emu.bus_control(json!({"overload": 3}))?;
    let bits = "state Safe(ServoError { joint: 2, id: 3, error: 0 }) -> \
                Safe(ServoError { joint: 2, id: 3, error: 32 }) on ErrorBits";
    board.wait_for_log(bits, s)?;
    emu.run_for(Duration::from_millis(200))?;

    // The empty store has no joint map, so the first boot ends at once; the upload brings one and
    // the board looks for its servos; Play ramps, then walks; the overload stops it.
    let want = [
        "state Boot -> Idle on Event(BootDone)",
        "state Idle -> Boot on NewJointMap",
        "state Boot -> Idle on Event(BootDone)",
        "state Idle -> Ramping on Event(Start)",
        "state Ramping -> Walking on Event(RampDone)",
        "state Walking -> Safe(ServoError { joint: 2, id: 3, error: 0 }) on \
         Event(Fault(ServoError { joint: 2, id: 3, error: 0 }))",
        bits,
    ];
    let lines: Vec<String> = emu
        .logs()
        .into_iter()
        .map(|l| l.text)
        .filter(|t| t.contains("state ") || t.contains("fault "))
        .collect();
    println!("{}", lines.join("\n"));
    let got: Vec<&str> = lines
        .iter()
        .map(|t| t.find("state ").map_or(t.as_str(), |i| &t[i..]))
        .collect();
    ensure!(
        got == want,
        "logged state changes:\n{}\nexpected:\n{}",
        got.join("\n"),
        want.join("\n")
    );
    Ok(())
}

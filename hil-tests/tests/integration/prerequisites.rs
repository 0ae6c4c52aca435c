//! The test command runs the emulator tests or fails (issue #19, item 9): a missing prerequisite
//! of the emulator is an error naming it, not a skip that passes. Before, without `CI` set, a
//! missing firmware image printed SKIPPED and the test passed, and `scripts/test.sh` does not set
//! `CI`. `DBOT_HIL_OPTIONAL=1` is the explicit opt-out; with it the same start is a skip.

use std::path::PathBuf;

use hil_tests::emulator::Options;
use hil_tests::target::{OPTIONAL_ENV, Target};

#[test]
fn a_missing_firmware_image_fails_the_emulator_test_naming_it() {
    if std::env::var_os("DBOT_HIL_PORT").is_some() {
        // A real board needs no emulator; the rule is about the emulator's prerequisites.
        eprintln!("real-board run (DBOT_HIL_PORT): the emulator is not started");
        return;
    }
    let elf = PathBuf::from("/nonexistent/firmware.elf");
    let opts = Options {
        elf: Some(elf.clone()),
        ..Options::default()
    };
    let started = Target::start("prerequisites", opts);
    let opted_out = std::env::var_os(OPTIONAL_ENV).is_some_and(|v| !v.is_empty() && v != "0");
    match (started, opted_out) {
        (Err(e), false) => {
            let msg = format!("{e:#}");
            assert!(msg.contains("/nonexistent/firmware.elf"), "{msg}");
            assert!(msg.contains(OPTIONAL_ENV), "{msg}");
        }
        (Ok(None), true) => {}
        (Ok(Some(_)), _) => panic!("an emulator started without its firmware image"),
        (Ok(None), false) => panic!("a missing firmware image was a skip that passes"),
        (Err(e), true) => panic!("{OPTIONAL_ENV} is set but the start failed: {e:#}"),
    }
}

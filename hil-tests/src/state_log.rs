//! The firmware's state changes as its defmt log states them (firmware/src/device_log.rs), read from
//! the emulator, and the changes every walk from an empty store begins with.

use crate::Emulator;
use anyhow::{Result, ensure};

/// An empty store has no joint map, so the first boot ends at once; the upload brings one and the
/// board looks for its servos again; Play ramps, then walks.
pub const UPLOAD_AND_WALK: [&str; 5] = [
    "state Boot -> Idle on Event(BootDone)",
    "state Idle -> Boot on NewJointMap",
    "state Boot -> Idle on Event(BootDone)",
    "state Idle -> Ramping on Event(Start)",
    "state Ramping -> Walking on Event(RampDone)",
];

/// The log lines so far that state a change or a fault, whole (with the firmware time in front).
pub fn state_lines(emu: &Emulator) -> Vec<String> {
    emu.logs()
        .into_iter()
        .map(|l| l.text)
        .filter(|t| t.contains("state ") || t.contains("fault "))
        .collect()
}

/// Fails unless `lines` ([`state_lines`]), each from its "state " on, are `want` in order.
pub fn ensure_state_changes(lines: &[String], want: &[&str]) -> Result<()> {
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

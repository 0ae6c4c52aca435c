//! The official ROBOTIS Dynamixel SDK (Python, pinned in requirements-dev.txt) against
//! `dbot sim-bus`: ping all 22 IDs, broadcast ping, model numbers, goal writes, Sync Write,
//! Sync Read. Needs `.venv` (scripts/setup.d/10-venv.sh).

use crate::sim_bus_support;
use std::path::PathBuf;
use std::process::Command;

#[test]
fn python_sdk_drives_the_virtual_bus() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let python = root.join(".venv/bin/python");
    assert!(
        python.exists(),
        "{} is missing: run scripts/setup.d/10-venv.sh to create the Python venv with dynamixel-sdk",
        python.display()
    );
    // Factory Return Delay Time (250 = 500 us), as a fresh servo has it.
    let bus = sim_bus_support::SimBus::start(22, 1_000_000, 250);
    // Where the model file puts the MX-64s (the SDK reads their model number, 311, there).
    let mx64: Vec<String> = planner::model::builtin("drosophibot2")
        .unwrap()
        .servo_chain()
        .into_iter()
        .filter(|s| s.1 == dynamixel::ServoModel::Mx64)
        .map(|s| s.0.to_string())
        .collect();
    assert_eq!(mx64.len(), 6);
    let out = Command::new(&python)
        .arg(root.join("host/dbot/tests/integration/sdk/sdk_check.py"))
        .arg(bus.link())
        .args(["1000000", "22", &mx64.join(",")])
        .output()
        .expect("run the SDK script");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "SDK check failed:\n{stdout}\n{stderr}\nsim-bus said (last lines):\n{}",
        tail(&bus.log(), 30)
    );
    assert!(stdout.contains("PASS"), "{stdout}");
    let log = bus.log();
    assert!(
        log.contains("Sync Write") && log.contains("Sync Read"),
        "sim-bus log lacks the sync requests:\n{log}"
    );
}

fn tail(s: &str, n: usize) -> String {
    let lines: Vec<&str> = s.lines().collect();
    lines[lines.len().saturating_sub(n)..].join("\n")
}

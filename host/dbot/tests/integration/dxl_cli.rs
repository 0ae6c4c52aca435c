//! `dbot dxl` against `dbot sim-bus`, as a user would set up real servos: scan, read, write,
//! and setup (Return Delay Time, ID, baud) followed by a scan at the new baud.

use crate::sim_bus_support;
use std::process::Command;

fn dxl(link: &std::path::Path, baud: u32, args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_dbot"))
        .arg("dxl")
        .args(args)
        .arg("--port")
        .arg(link)
        .args(["--baud", &baud.to_string()])
        // Generous: a loaded CI machine can deschedule the server for tens of milliseconds, and
        // every absent ID of a scan costs one slack.
        .args(["--reply-slack-us", "300000"])
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("run dbot dxl");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    (out.status.success(), text)
}

#[test]
fn scan_read_write_and_setup_work_as_on_real_servos() {
    let bus = sim_bus_support::SimBus::start(6, 1_000_000, 250);
    let link = bus.link();

    let (ok, out) = dxl(link, 1_000_000, &["scan", "--max-id", "7"]);
    assert!(ok, "{out}");
    assert!(
        out.contains("6 servo(s) found"),
        "{out}\nsim-bus said:\n{}",
        bus.log()
    );
    assert!(out.contains("6 servo(s) found"), "{out}");
    assert!(out.contains("ID   3: model 311 (MX-64(2.0))"), "{out}");
    assert!(out.contains("ID   1: model 30 (MX-28(2.0))"), "{out}");

    let (ok, out) = dxl(
        link,
        1_000_000,
        &[
            "write",
            "--id",
            "2",
            "--field",
            "Goal Position",
            "--value",
            "1234",
        ],
    );
    assert!(ok, "{out}");
    let (ok, out) = dxl(
        link,
        1_000_000,
        &["read", "--id", "2", "--field", "goal_position"],
    );
    assert!(ok && out.contains("= 1234 "), "{out}");

    // Bad input names the problem.
    let (ok, out) = dxl(
        link,
        1_000_000,
        &["read", "--id", "2", "--field", "Goal Positon"],
    );
    assert!(!ok && out.contains("no such control table field"), "{out}");
    let (ok, out) = dxl(
        link,
        1_000_000,
        &["write", "--id", "2", "--field", "LED", "--value", "300"],
    );
    assert!(!ok && out.contains("does not fit in 1 byte"), "{out}");

    let setup = [
        "setup",
        "--id",
        "4",
        "--new-id",
        "8",
        "--new-baud",
        "2000000",
        "--return-delay-us",
        "0",
    ];
    let (ok, out) = dxl(link, 1_000_000, &setup);
    assert!(ok, "{out}");
    assert!(out.contains("ID 8 answers"), "{out}");
    // At the old baud the servo is gone; at the new one it is the only one.
    let (_, out) = dxl(link, 1_000_000, &["scan", "--max-id", "8"]);
    assert!(
        out.contains("5 servo(s) found") && !out.contains("ID   8"),
        "{out}"
    );
    let (_, out) = dxl(link, 2_000_000, &["scan", "--max-id", "8"]);
    assert!(
        out.contains("1 servo(s) found") && out.contains("ID   8: model 30"),
        "{out}"
    );
    let (ok, out) = dxl(
        link,
        2_000_000,
        &["read", "--id", "8", "--field", "Return Delay Time"],
    );
    assert!(ok && out.contains("= 0 "), "{out}");
}

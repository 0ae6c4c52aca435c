//! `dbot demo` end to end (shortened to 2 steps each way): every output is written, and the
//! summary's numbers agree with the files the run wrote.

use crate::board_fakes;
use std::process::Command;

use board_fakes::cli::DEMO_FILES;

fn number_after(text: &str, marker: &str) -> f64 {
    let rest = &text[text
        .find(marker)
        .unwrap_or_else(|| panic!("no `{marker}` in:\n{text}"))
        + marker.len()..];
    let tok: String = rest
        .trim_start()
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == '.')
        .collect();
    tok.parse()
        .unwrap_or_else(|_| panic!("no number after `{marker}`"))
}

#[test]
fn the_demo_walks_both_ways_and_its_summary_matches_its_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("demo");
    let o = Command::new(env!("CARGO_BIN_EXE_dbot"))
        .args(["demo", "--steps", "2", "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    for f in DEMO_FILES {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    // The step table is the one the summary names, and it parses.
    let table = std::fs::read(out.join("drosophibot2-tripod.dbgt")).unwrap();
    let t = protocol::GaitTable::parse(&table).unwrap();
    assert_eq!(t.joint_count(), 22);
    assert_eq!(
        number_after(&stdout, "drosophibot2-tripod.dbgt (") as usize,
        table.len()
    );
    // Recorded cycles in the summary = data rows / 22 joints in each CSV.
    for label in ["forward", "backward"] {
        let csv =
            std::fs::read_to_string(out.join("record").join(label).join("telemetry.csv")).unwrap();
        let rows = csv.lines().count() - 1;
        assert_eq!(rows % 22, 0);
        let line = stdout
            .lines()
            .find(|l| l.starts_with(&format!("tracking error {label}")))
            .unwrap();
        assert_eq!(
            number_after(line, "joints and cycles;") as usize,
            rows / 22,
            "{line}"
        );
    }
    // The planned period: 2.5 s (table 1 at the servo-safe swing, T_sw 1.0 s / (1 - 0.6)), and
    // the demo says that the servos can follow it before it uploads the table.
    let period = number_after(&stdout, "step period");
    assert!((period - 2.5).abs() < 1e-9, "{period}");
    let verdict = stdout
        .find("servos can follow the plan")
        .unwrap_or_else(|| panic!("no feasibility verdict:\n{stdout}"));
    assert!(
        verdict < stdout.find("[3/7] uploading").unwrap(),
        "{stdout}"
    );
    // Per-leg tracking lines for all six legs, for each walk (forward, backward, forward without
    // the torque bias).
    for leg in ["LF", "LM", "LH", "RF", "RM", "RH"] {
        assert_eq!(stdout.matches(&format!("  {leg}: RMS")).count(), 3, "{leg}");
    }
    // The bus ran at the firmware's default 100 Hz on the simulated clock.
    assert!(
        (number_after(&stdout, "s:") - 100.0).abs() < 0.5,
        "{stdout}"
    );
}

//! `dbot demo` walks the physics robot: its report carries the body's figures, each within
//! physical bounds and none equal to the plan by construction (a MuJoCo body sags, tilts and
//! slips; the planned figures are exact: 0.1417 m per step, no turn, no sag, no tilt, no slip).

use std::process::Command;

/// The numbers after `key` in `line` (up to the next non-number).
fn number_after(text: &str, key: &str) -> f64 {
    let at = text
        .find(key)
        .unwrap_or_else(|| panic!("no `{key}` in the report:\n{text}"));
    let rest = text[at + key.len()..].trim_start();
    let end = rest
        .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-' || c == '+'))
        .unwrap_or(rest.len());
    rest[..end]
        .parse()
        .unwrap_or_else(|e| panic!("`{key}` followed by `{}`: {e}", &rest[..end]))
}

#[test]
fn the_demo_reports_the_physics_robots_walk_within_physical_bounds() {
    let dir = tempfile::tempdir().unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_dbot"))
        .current_dir(dir.path())
        .args(["demo", "--steps", "2", "--out", "demo"])
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        o.status.success(),
        "{out}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(out.contains("bus (physics robot"), "{out}");
    for label in ["forward", "backward"] {
        let at = out
            .find(&format!("body {label} (physics robot"))
            .unwrap_or_else(|| panic!("no body figures for the {label} walk:\n{out}"));
        let body = &out[at..];
        let body = &body[..body[1..].find("\nbody ").map_or(body.len(), |e| e + 1)];
        // Table 1: 0.085 m stroke in 0.75 s of stance, 1.25 s cycles: 0.1417 m per step.
        let planned = number_after(body, "planned");
        assert!((planned - 0.085 / 0.75 * 1.25).abs() < 1e-3, "{body}");
        let walked = number_after(body, "distance");
        // Within 15 % of the plan (start ramp and stop included), but not the plan itself.
        assert!((walked - planned).abs() < 0.15 * planned, "{body}");
        assert!(
            (walked - planned).abs() > 1e-4,
            "distance equals the plan: {body}"
        );
        let heading = number_after(body, "heading drift");
        assert!(heading.abs() < 5.0, "{body}");
        let start = number_after(body, "thorax height");
        let lowest = number_after(body, "mm at the start,");
        // A 5 kg body on compliant servos sags, by millimetres, not centimetres.
        assert!(lowest < start - 0.1 && lowest > start - 10.0, "{body}");
        let tilt = number_after(body, "tilt up to");
        assert!(tilt > 0.01 && tilt < 10.0, "{body}");
        for leg in ["LF", "LM", "LH", "RF", "RM", "RH"] {
            let slip = number_after(body, &format!("{leg} "));
            assert!((0.0..30.0).contains(&slip), "{leg} slip {slip} mm: {body}");
        }
        assert!(body.contains("the robot carried the gait"), "{body}");
    }
}

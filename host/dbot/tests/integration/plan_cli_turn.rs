//! `dbot plan --turn/--radius` end to end: the curve lands in plan.json as the rotation and
//! stride worked out by hand, and nonsense is refused naming the flag, the parameter and its range.

use std::process::Command;

fn dbot(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_dbot"))
        .args(args)
        .output()
        .unwrap()
}

/// `dbot plan` (servo-safe, 40 slices, no dynamics) with `extra`; the plan.json parameters.
fn plan(extra: &[&str]) -> Result<serde_json::Value, String> {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let mut args = vec!["plan", "--slices", "40", "--no-dynamics", "--out", out];
    args.extend_from_slice(extra);
    let o = dbot(&args);
    if !o.status.success() {
        return Err(String::from_utf8_lossy(&o.stderr).into_owned());
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("plan.json")).unwrap())
            .unwrap();
    Ok(json["parameters"].clone())
}

fn f(v: &serde_json::Value, k: &str) -> f64 {
    v[k].as_f64().unwrap()
}

#[test]
fn turn_and_radius_flags_plan_the_curve_worked_out_by_hand() {
    // servo-safe: stride 0.085 m per stance, duty 0.6.
    // --turn -12: rotation -12 deg x 0.6 = -7.2 deg = -0.125664 rad per stance, stride kept.
    let p = plan(&["--turn", "-12"]).unwrap();
    assert!((f(&p, "rotation_rad") + 0.125_663_706).abs() < 1e-8, "{p}");
    assert_eq!(f(&p, "translation_m"), 0.085);
    // --radius 0.5: rotation 0.085 / 0.5 = 0.17 rad per stance.
    let p = plan(&["--radius", "0.5"]).unwrap();
    assert!((f(&p, "rotation_rad") - 0.17).abs() < 1e-12, "{p}");
    // On the spot: --turn 20 --radius 0: 0.20944 rad per stance, no stride.
    let p = plan(&["--turn", "20", "--radius", "0"]).unwrap();
    assert!((f(&p, "rotation_rad") - 0.209_439_510).abs() < 1e-8, "{p}");
    assert_eq!(f(&p, "translation_m"), 0.0);
}

#[test]
fn nonsense_turns_are_refused_naming_the_parameter_and_range() {
    for (args, words) in [
        (&["--turn", "200"][..], "-180 and 180 deg"),
        (&["--radius", "0"][..], "radius 0 turns on the spot"),
        (&["--radius", "250"][..], "-100 and 100 m"),
        (
            &["--turn", "0", "--radius", "0.3"][..],
            "a radius needs a turn",
        ),
    ] {
        let e = plan(args).unwrap_err();
        assert!(
            e.contains("--turn/--radius") && e.contains(words),
            "{args:?}: {e}"
        );
    }
    let e = plan(&["--turn", "10", "--radius", "0.4", "--backward"]).unwrap_err();
    assert!(e.contains("--backward with --turn and --radius"), "{e}");
}

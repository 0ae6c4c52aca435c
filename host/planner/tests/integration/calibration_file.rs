//! The model file's `calibration = "..."` (docs/identification.md, "Calibrated readings"): the
//! named file is read relative to the model file, its joint entries override the Present Load
//! reading, its gauge gains are kept, and a bad file is refused naming the file, the joint or
//! gauge and the field.

use planner::model::{builtin, load, to_toml_string};

/// The built-in Drosophibot II written to `dir/model.toml` naming `cal.toml`, with `cal` as that
/// file; loaded.
fn load_with(dir: &std::path::Path, cal: &str) -> Result<planner::model::Model, String> {
    let m = builtin("drosophibot2").unwrap();
    let text = to_toml_string(&m, "", &|_| String::new());
    std::fs::write(
        dir.join("model.toml"),
        format!("calibration = \"cal.toml\"\n{text}"),
    )
    .unwrap();
    std::fs::write(dir.join("cal.toml"), cal).unwrap();
    load(&dir.join("model.toml")).map_err(|e| e.to_string())
}

#[test]
fn a_named_calibration_overrides_the_load_reading_and_gives_gauge_gains() {
    let dir = tempfile::tempdir().unwrap();
    let m = load_with(
        dir.path(),
        "trial = \"t\"\n[joint.LF_CTr]\nload_gain = 0.8\nload_offset_nm = 0.05\nr2 = 0.9\nsamples = 10\n\
         [gauge.LF_troch_axial]\ncounts_per_microstrain = 0.7\n",
    )
    .unwrap();
    let j = m.joint_index("LF_CTr").unwrap();
    let p = m.servo_params(j).unwrap();
    assert_eq!((p.load_gain, p.load_offset_nm), (0.8, 0.05));
    // A joint the file does not name keeps the default reading (exact, gain 1).
    let other = m.servo_params(m.joint_index("LM_CTr").unwrap()).unwrap();
    assert_eq!((other.load_gain, other.load_offset_nm), (1.0, 0.0));
    let cal = m.calibration.as_ref().unwrap();
    assert_eq!(cal.gauge_gain("LF_troch_axial"), Some(0.7));
    assert_eq!(cal.gauge_gain("LM_troch_axial"), None);
    assert!(cal.path.is_absolute() && cal.path.ends_with("cal.toml"));
    // Written back out, the model names the file by its absolute path and loads the same.
    let again = dir.path().join("again");
    std::fs::create_dir(&again).unwrap();
    std::fs::write(
        again.join("m.toml"),
        to_toml_string(&m, "", &|_| String::new()),
    )
    .unwrap();
    let m2 = load(&again.join("m.toml")).unwrap();
    assert_eq!(m2.calibration, m.calibration);
}

#[test]
fn a_bad_calibration_is_refused_naming_the_file_the_gauge_or_joint_and_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let cal = dir.path().join("cal.toml").display().to_string();
    let e = load_with(
        dir.path(),
        "[gauge.LF_troch_axial]\ncounts_per_microstrain = -0.5\n",
    )
    .unwrap_err();
    assert!(
        e.contains(&cal)
            && e.contains("gauge LF_troch_axial")
            && e.contains("counts_per_microstrain"),
        "{e}"
    );
    let e = load_with(
        dir.path(),
        "[gauge.LF_nonsense]\ncounts_per_microstrain = 0.5\n",
    )
    .unwrap_err();
    assert!(
        e.contains(&cal) && e.contains("unknown gauge `LF_nonsense`"),
        "{e}"
    );
    let e = load_with(
        dir.path(),
        "[joint.LF_CTr]\nload_gain = 0\nload_offset_nm = 0\n",
    )
    .unwrap_err();
    assert!(
        e.contains(&cal) && e.contains("joint LF_CTr") && e.contains("load_gain"),
        "{e}"
    );
    // A TOML error names the file and the line.
    let e = load_with(
        dir.path(),
        "[gauge.LF_troch_axial]\ncounts_per_microstrain = \"x\"\n",
    )
    .unwrap_err();
    assert!(e.contains(&cal) && e.contains("line 2"), "{e}");
    // A missing file is named by the model file's field.
    std::fs::write(
        dir.path().join("m2.toml"),
        format!(
            "calibration = \"missing.toml\"\n{}",
            to_toml_string(&builtin("drosophibot2").unwrap(), "", &|_| String::new())
        ),
    )
    .unwrap();
    let e = load(&dir.path().join("m2.toml")).unwrap_err().to_string();
    assert!(
        e.contains("m2.toml") && e.contains("calibration") && e.contains("missing.toml"),
        "{e}"
    );
}

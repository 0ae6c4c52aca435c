//! docs/validation.md quotes run results; `dbot validate --check` regenerates them (built-in
//! models, feasibility, the incline error, the paper's comparison) and fails naming every generated
//! block of the document that differs, so the document cannot drift from the code. The paper's own
//! figures in the document are its statements, quoted beside ours (`planner::analysis::paper`).

use std::process::Command;

#[test]
fn validation_md_matches_a_fresh_run_and_drift_is_named() {
    // One run (the check plans and solves about 15 cycles): the document with one figure changed
    // (the old drift, 49.48 N for the robot's 49.06 N weight) must fail naming that block only,
    // so every other block matches the fresh run.
    let doc = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/validation.md");
    let text = std::fs::read_to_string(doc).unwrap();
    assert!(
        text.contains("weight 49.06 N"),
        "docs/validation.md no longer quotes the robot's weight as 49.06 N"
    );
    let dir = std::env::temp_dir().join(format!("validation-drift-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("validation.md");
    std::fs::write(&path, text.replacen("weight 49.06 N", "weight 49.48 N", 1)).unwrap();
    // The plots beside it, one of them missing: named as drifted too.
    let plots = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/validation");
    std::fs::create_dir_all(dir.join("validation")).unwrap();
    for f in std::fs::read_dir(plots).unwrap() {
        let f = f.unwrap().path();
        let name = f.file_name().unwrap().to_owned();
        if name != "fly_flat_torques.png" {
            std::fs::copy(&f, dir.join("validation").join(name)).unwrap();
        }
    }
    let o = Command::new(env!("CARGO_BIN_EXE_dbot"))
        .args(["validate", "--check", path.to_str().unwrap()])
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&o.stderr).into_owned();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(!o.status.success());
    assert!(
        e.contains(
            "has drifted from the code in block(s) weight, validation/fly_flat_torques.png:"
        ),
        "expected only the `weight` block and the missing plot to differ (run `dbot validate --write docs/validation.md` if the code changed on purpose):\n{e}"
    );
}

//! `dbot plan --spring paper --body-height-offset ...`: plan.json names the three stiffnesses apart
//! (actuator, parallel spring, their sum), the springs rest at the resting posture, the per-pair
//! body heights are table 1's plus the offsets, and at a 4 s period `dbot table` accepts the plan;
//! `--spring-equilibrium dead-fly` reaches plan.json and the plan directory's model file.

use std::process::Command;

fn dbot(dir: &std::path::Path, args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_dbot"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

/// `dbot plan --spring paper EXTRA --slices 40 --out p` in a fresh directory named for `tag` and
/// this process: the directory and what the plan printed.
fn plan_with_springs(tag: &str, extra: &[&str]) -> (std::path::PathBuf, std::process::Output) {
    let dir = std::env::temp_dir().join(format!("{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut args = vec!["plan", "--spring", "paper"];
    args.extend_from_slice(extra);
    args.extend(["--slices", "40", "--out", "p"]);
    let o = dbot(&dir, &args);
    (dir, o)
}

#[test]
fn springs_and_body_height_offsets_reach_plan_json() {
    let (dir, o) = plan_with_springs(
        "plan-cli-springs",
        &["--body-height-offset", "0,0.015,-0.01", "--swing", "1.6"],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("p/plan.json")).unwrap()).unwrap();
    let d = &json["dynamics"];
    let act = d["actuator_stiffness_nm_per_rad"]["LF_CTr"]
        .as_f64()
        .unwrap();
    let spring = &d["parallel_spring"]["LF_CTr"];
    assert_eq!(spring["stiffness_nm_per_rad"].as_f64(), Some(1.0));
    assert_eq!(
        spring["equilibrium_rad"].as_f64(),
        json["resting_posture_rad"]["LF_CTr"].as_f64()
    );
    assert_eq!(spring["equilibrium_from"].as_str(), Some("RestingPosture"));
    // Joint stiffness = actuator + parallel spring; the robot's CTr actuator is 34.29 N m/rad.
    assert!((act - 34.2857142857).abs() < 1e-9);
    let joint = d["joint_stiffness_nm_per_rad"]["LF_CTr"].as_f64().unwrap();
    assert!((joint - (act + 1.0)).abs() < 1e-12);
    // Fixed joints have neither.
    assert!(d["parallel_spring"]["LM_ThC1"].is_null());
    // Table 1's 0.175 m per pair plus the offsets.
    let h = &json["parameters"]["body_height_m"];
    assert!((h["middle"].as_f64().unwrap() - 0.190).abs() < 1e-12);
    assert!((h["front"].as_f64().unwrap() - 0.165).abs() < 1e-12);
    assert!(json["feasibility"]["feasible"].as_bool().unwrap());
    let o = dbot(&dir, &["table", "--plan", "p", "--out", "t.dbgt"]);
    let _ = std::fs::remove_dir_all(&dir);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn dead_fly_equilibrium_reaches_plan_json_and_the_model_file() {
    // --spring-equilibrium dead-fly: the CTr springs rest at -35 deg = -0.6108652 rad (the
    // original solver's, ../shared/reference/solver.md), recorded so that a re-plan from the plan
    // directory's model.toml resolves the same proxy.
    let (dir, o) = plan_with_springs("plan-cli-dead-fly", &["--spring-equilibrium", "dead-fly"]);
    let json = std::fs::read_to_string(dir.join("p/plan.json"));
    let model = std::fs::read_to_string(dir.join("p/model.toml"));
    let _ = std::fs::remove_dir_all(&dir);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let json: serde_json::Value = serde_json::from_str(&json.unwrap()).unwrap();
    assert_eq!(
        json["spring_args"]["spring_equilibrium"].as_str(),
        Some("dead-fly")
    );
    let spring = &json["dynamics"]["parallel_spring"]["LF_CTr"];
    assert_eq!(spring["equilibrium_from"].as_str(), Some("DeadFly"));
    let eq = spring["equilibrium_rad"].as_f64().unwrap();
    assert!((eq - -0.610_865_238).abs() < 1e-9, "{eq}");
    let model = model.unwrap();
    assert!(model.contains("equilibrium = \"dead_fly\""), "{model}");
    assert!(!model.contains("equilibrium = \"rest\""));
}

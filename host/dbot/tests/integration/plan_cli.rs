//! The `dbot plan` and `dbot model export` commands end to end: files written as issue 5 specifies.

use std::process::Command;

fn dbot(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_dbot"))
        .args(args)
        .output()
        .unwrap()
}

/// `dbot model export --model MODEL FLAG FILE`.
fn export(model: &str, flag: &str, file: &std::path::Path) -> std::process::Output {
    dbot(&[
        "model",
        "export",
        "--model",
        model,
        flag,
        file.to_str().unwrap(),
    ])
}

#[test]
fn plan_writes_every_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let o = dbot(&[
        "plan",
        "--model",
        "drosophibot2",
        "--terrain",
        "incline:15",
        "--gait",
        "tripod",
        "--swing",
        "0.6",
        "--slices",
        "40",
        "--backward",
        "--out",
        out,
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for f in [
        "joints.csv",
        "feet.csv",
        "plan.json",
        "model.urdf",
        "joint_angles.png",
        "footfall.png",
        "feet.png",
        "robot.png",
        "step.gif",
    ] {
        assert!(dir.path().join(f).metadata().unwrap().len() > 0, "{f}");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("plan.json")).unwrap())
            .unwrap();
    assert_eq!(json["parameters"]["swing_s"], 0.6);
    assert_eq!(json["slices"], 40);
    assert!(json["parameters"]["translation_m"].as_f64().unwrap() < 0.0);
    // Period = swing / (1 - duty) = 0.6 / 0.4.
    assert!((json["period_s"].as_f64().unwrap() - 1.5).abs() < 1e-12);
    let g = json["gravity_m_s2"].as_array().unwrap();
    assert!((g[0].as_f64().unwrap() + 9.81 * 15f64.to_radians().sin()).abs() < 1e-9);
    let joints = std::fs::read_to_string(dir.path().join("joints.csv")).unwrap();
    assert_eq!(joints.lines().count(), 1 + 40 * 32);
    assert!(urdf_rs::read_file(dir.path().join("model.urdf")).is_ok());
}

#[test]
fn params_file_and_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let params = dir.path().join("p.toml");
    let plan_with_params = || {
        dbot(&[
            "plan",
            "--params",
            params.to_str().unwrap(),
            "--out",
            dir.path().to_str().unwrap(),
        ])
    };
    std::fs::write(&params, "duty = 1.5\n").unwrap();
    let o = plan_with_params();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("duty"));
    std::fs::write(&params, "dutty = 0.5\n").unwrap();
    let o = plan_with_params();
    assert!(String::from_utf8_lossy(&o.stderr).contains("dutty"));
}

#[test]
fn model_export_urdf() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("fly.urdf");
    let o = export("scale-drosophila", "--urdf", &f);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let robot = urdf_rs::read_file(&f).unwrap();
    assert!(robot.links.iter().any(|l| l.name == "LF_tip"));
    assert!(robot.joints.iter().any(|j| j.name == "LF_ThC1"));
}

/// The `timestep` attribute of an MJCF file, s.
fn mjcf_timestep(path: &std::path::Path) -> f64 {
    let xml = std::fs::read_to_string(path).unwrap();
    let at = xml.find("timestep=\"").expect("an <option timestep>") + "timestep=\"".len();
    xml[at..at + xml[at..].find('"').unwrap()].parse().unwrap()
}

#[test]
fn model_export_mjcf_writes_a_timestep_at_which_the_model_does_not_ring() {
    let dir = tempfile::tempdir().unwrap();
    // The robot: its stiffest joint rings at about 63 rad/s, far inside 0.5 ms (omega dt 0.03).
    let robot = dir.path().join("robot.xml");
    let o = export("drosophibot2", "--mjcf", &robot);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(mjcf_timestep(&robot), 5e-4);
    assert!(
        o.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    // The fly: 3.8e-8 N m/rad on 5.06e-15 kg m^2 rings at sqrt(3.8e-8 / 5.06e-15) = 2740 rad/s;
    // omega dt <= 0.3 needs dt <= 0.109 ms, rounded down to 0.1 ms, and the export says why.
    let fly = dir.path().join("fly.xml");
    let o = export("scale-drosophila", "--mjcf", &fly);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!((mjcf_timestep(&fly) - 1e-4).abs() < 1e-12);
    let said = String::from_utf8_lossy(&o.stdout);
    assert!(
        said.contains("scale-drosophila")
            && said.contains("0.1 ms")
            && said.contains("2740 rad/s")
            && said.contains("stable below 0.109 ms"),
        "{said}"
    );
}

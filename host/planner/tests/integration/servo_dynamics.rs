//! Servo dynamics in the model file (docs/models.md, "Servo dynamics"): the built-in model's
//! sections are the defaults of code, errors name file, place, field and range, a joint's field
//! beats its servo model's which beats the default, a model round-trips through TOML, and the
//! MJCF export carries damping, frictionloss and armature.

use planner::model::{
    MjcfOptions, ServoParams, builtin, from_toml_str, joint_actuator, to_mjcf, to_toml_string,
};
use protocol::ServoModel;

const BUILTIN: &str = include_str!("../../models/drosophibot2.toml");

/// The built-in model's text without its `[servo_dynamics.*]` sections, with `sections` in their
/// place and `joint_extra` added to joint LF_CTr (servo ID 3, an MX-64).
fn model_text(sections: &str, joint_extra: &str) -> String {
    let start = BUILTIN.find("[servo_dynamics.mx28]").unwrap();
    let end = BUILTIN.find("[[body]]").unwrap();
    let mut text = format!("{}{sections}\n{}", &BUILTIN[..start], &BUILTIN[end..]);
    let servo = "servo = { id = 3, zero_offset_rad = 0.0, sign = 1 }";
    assert_eq!(text.matches(servo).count(), 1);
    text = text.replace(servo, &format!("{servo}\n{joint_extra}"));
    text
}

fn error_of(text: &str) -> String {
    from_toml_str(text, "robot.toml").unwrap_err().to_string()
}

#[test]
fn the_builtin_models_sections_are_the_defaults_of_code() {
    // Written out in host/planner/models/drosophibot2.toml, they must be the very values the
    // physics robot used before they were in the file (dynamixel::ServoModel's, bit for bit).
    let m = builtin("drosophibot2").unwrap();
    let mut servos = 0;
    for (j, joint) in m.joints.iter().enumerate() {
        let Some(p) = m.servo_params(j) else {
            continue;
        };
        servos += 1;
        let model = joint.servo.unwrap().model;
        assert_eq!(p, ServoParams::defaults(model), "{}", joint.name);
    }
    assert_eq!(servos, 22);
    // e-manual: MX-28 2.5 N m and 55 rev/min, MX-64 6.0 N m and 63 rev/min at 12 V.
    let d = ServoParams::defaults(ServoModel::Mx64);
    assert_eq!(d.stall_torque_nm, 6.0);
    assert!((d.no_load_speed_rad_s - 63.0 * std::f64::consts::TAU / 60.0).abs() < 1e-5);
    assert_eq!((d.i_gain, d.d_gain, d.p_gain_divisor), (0, 0, 128.0));
    // The fly has no servos: no servo dynamics.
    let fly = builtin("scale-drosophila").unwrap();
    assert!((0..fly.joints.len()).all(|j| fly.servo_params(j).is_none()));
}

#[test]
fn a_joints_field_beats_its_servo_models_which_beats_the_default() {
    let text = model_text(
        "[servo_dynamics.mx64]\nfriction_nm = 0.05\nbacklash_rad = 0.003\n",
        "servo_dynamics = { friction_nm = 0.07, load_gain = 0.8 }",
    );
    let m = from_toml_str(&text, "robot.toml").unwrap();
    let p = |name: &str| m.servo_params(m.joint_index(name).unwrap()).unwrap();
    // LF_CTr (MX-64): its own friction and load gain, its model's backlash.
    let lf = p("LF_CTr");
    assert_eq!(
        (lf.friction_nm, lf.load_gain, lf.backlash_rad),
        (0.07, 0.8, 0.003)
    );
    // RF_CTr (MX-64): the model's friction and backlash, the default load gain.
    let rf = p("RF_CTr");
    assert_eq!(
        (rf.friction_nm, rf.load_gain, rf.backlash_rad),
        (0.05, 1.0, 0.003)
    );
    // LF_ThC1 (MX-28, no section): every default.
    assert_eq!(p("LF_ThC1"), ServoParams::defaults(ServoModel::Mx28));
    // And back through the file format unchanged.
    let again = from_toml_str(&to_toml_string(&m, "", &|_| String::new()), "again.toml").unwrap();
    assert_eq!(again.servo_dynamics, m.servo_dynamics);
    assert_eq!(
        again.servo_params(m.joint_index("LF_CTr").unwrap()),
        Some(lf)
    );
}

#[test]
fn bad_servo_dynamics_are_refused_naming_file_place_field_and_range() {
    // Out of range on a joint.
    let e = error_of(&model_text("", "servo_dynamics = { backlash_rad = 0.5 }"));
    for part in [
        "robot.toml",
        "joint LF_CTr",
        "servo_dynamics.backlash_rad",
        "0.5 rad",
        "0 ..= 0.2 rad",
    ] {
        assert!(e.contains(part), "`{part}` not in: {e}");
    }
    // Out of range in a servo model's section.
    let e = error_of(&model_text(
        "[servo_dynamics.mx28]\nload_resolution_counts = 0\n",
        "",
    ));
    for part in [
        "robot.toml",
        "servo_dynamics.mx28",
        "load_resolution_counts",
        "1 ..= 1000 counts",
    ] {
        assert!(e.contains(part), "`{part}` not in: {e}");
    }
    let e = error_of(&model_text(
        "[servo_dynamics.mx28]\nstall_torque_nm = -2.5\n",
        "",
    ));
    assert!(
        e.contains("stall_torque_nm") && e.contains("-2.5 N m"),
        "{e}"
    );
    // Friction the servo could never overcome.
    let e = error_of(&model_text("", "servo_dynamics = { friction_nm = 7.0 }"));
    assert!(
        e.contains("joint LF_CTr") && e.contains("friction_nm") && e.contains("stall torque 6"),
        "{e}"
    );
    // An unknown servo model, an unknown field.
    let e = error_of(&model_text(
        "[servo_dynamics.mx106]\nfriction_nm = 0.1\n",
        "",
    ));
    assert!(
        e.contains("servo_dynamics") && e.contains("mx106") && e.contains("mx28, mx64"),
        "{e}"
    );
    let e = error_of(&model_text("", "servo_dynamics = { backlash = 0.001 }"));
    assert!(e.contains("robot.toml") && e.contains("backlash"), "{e}");
    // On a joint without a servo (LM_ThC1 is fixed on Drosophibot II).
    let fixed = "leg = \"LM\"\nkind = \"ThC1\"";
    let text = model_text("", "");
    assert_eq!(text.matches(fixed).count(), 1);
    let text = text.replace(
        fixed,
        &format!("{fixed}\nservo_dynamics = {{ friction_nm = 0.01 }}"),
    );
    let e = error_of(&text);
    assert!(
        e.contains("joint LM_ThC1") && e.contains("has no servo"),
        "{e}"
    );
}

#[test]
fn the_mjcf_export_carries_damping_frictionloss_and_armature() {
    let text = model_text(
        "[servo_dynamics.mx64]\nstall_torque_nm = 5.0\nno_load_speed_rad_s = 4.0\n",
        "servo_dynamics = { damping_nm_s_per_rad = 0.02, friction_nm = 0.1, armature_kg_m2 = 0.01 }",
    );
    let m = from_toml_str(&text, "robot.toml").unwrap();
    let xml = to_mjcf(
        &m,
        &MjcfOptions::stance(&m, &planner::terrain::Ground::Flat).unwrap(),
    );
    let line = |name: &str, tag: &str| {
        xml.lines()
            .find(|l| l.contains(&format!("<{tag} name=\"{name}\"")))
            .unwrap_or_else(|| panic!("no {tag} {name}"))
            .to_owned()
    };
    // LF_CTr: its own values, written as {:e}.
    let hinge = line("LF_CTr", "joint");
    assert!(
        hinge.contains(r#"damping="2e-2" frictionloss="1e-1" armature="1e-2""#),
        "{hinge}"
    );
    // RF_CTr: the MX-64 default armature, 2 g cm^2 x 200^2 = 0.008 kg m^2; no damping or friction.
    let hinge = line("RF_CTr", "joint");
    assert!(
        hinge.contains(r#"damping="0e0" frictionloss="0e0" armature="8e-3""#),
        "{hinge}"
    );
    // Its actuator: the section's torque-speed line, kv = 5 N m / 4 rad/s = 1.25, limit 5 N m.
    let act = line("RF_CTr", "position");
    assert!(
        act.contains(r#"kv="1.25e0" forcerange="-5e0 5e0""#),
        "{act}"
    );
    let a = joint_actuator(&m, m.joint_index("RF_CTr").unwrap()).unwrap();
    assert_eq!((a.stall_nm, a.damping), (5.0, 1.25));
    // An MX-28 joint keeps the datasheet's: 2.5 N m over 55 rev/min.
    let act = line("LF_ThC1", "position");
    assert!(act.contains(r#"forcerange="-2.5e0 2.5e0""#), "{act}");
}

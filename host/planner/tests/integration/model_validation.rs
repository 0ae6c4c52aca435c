//! One validation for every model loader (issue #30 items 1 and 6): an .aproj with a NaN or
//! reversed limit on an actuated joint, physically impossible bodies (zero mass, an inertia that
//! no mass distribution has) and a leg without a foot are refused by the TOML loader and the
//! AnimatLab importer alike, naming the place and the field.

use crate::model_support;
use model_support::ONE_LEG as GOOD;

use planner::model::*;

/// The stripped Drosobot II project of the fuzzing seeds (imports to the built-in model).
const DROSOBOT2: &str = include_str!("../../../../fuzz/seeds/aproj/Drosobot2.aproj");
/// LF_CTr's lower limit in that project, degrees (its upper is `100`).
const LF_CTR_LOWER: &str = r#"<LimitPos Value="-47" Scale="None" />"#;

/// The Drosobot II project with LF_CTr's lower limit written as `value` degrees.
fn with_lf_ctr_lower(value: &str) -> String {
    let joint = DROSOBOT2.find("<Name>LF_CTr</Name>").unwrap();
    let at = joint + DROSOBOT2[joint..].find(LF_CTR_LOWER).unwrap();
    format!(
        r#"{}<LimitPos Value="{value}" Scale="None" />{}"#,
        &DROSOBOT2[..at],
        &DROSOBOT2[at + LF_CTR_LOWER.len()..]
    )
}

fn aproj_err(text: &str) -> String {
    import_aproj(text, "bad.aproj", &ImportOptions::default())
        .unwrap_err()
        .to_string()
}

fn toml_err(text: &str) -> String {
    from_toml_str(text, "bad.toml").unwrap_err().to_string()
}

const FEMUR_INERTIA: &str = "inertia_kg_m2 = [1e-5, 1e-4, 1e-4, 0.0, 0.0, 0.0]";

#[test]
fn the_seeds_and_the_built_in_models_pass_the_validation() {
    for text in [
        DROSOBOT2,
        include_str!("../../../../fuzz/seeds/aproj/ScaleDrosophila.aproj"),
        include_str!("../../../../fuzz/seeds/aproj/TypicalHexapod.aproj"),
    ] {
        let m = import_aproj(text, "seed.aproj", &ImportOptions::default()).unwrap();
        assert_eq!(m.feet.len(), 6);
    }
    for name in BUILTIN_NAMES {
        builtin(name).unwrap();
    }
    from_toml_str(GOOD, "good.toml").unwrap();
}

#[test]
fn an_aproj_with_a_nan_or_reversed_limit_on_an_actuated_joint_is_refused_naming_it() {
    let e = aproj_err(&with_lf_ctr_lower("NaN"));
    assert!(
        e.contains("bad.aproj") && e.contains("joint LF_CTr") && e.contains("limits"),
        "{e}"
    );
    assert!(e.contains("NaN"), "{e}");
    // 170 degrees above the upper limit of 100.
    let e = aproj_err(&with_lf_ctr_lower("170"));
    assert!(
        e.contains("joint LF_CTr") && e.contains("limits") && e.contains("lower below upper"),
        "{e}"
    );
}

#[test]
fn a_body_of_zero_mass_is_refused_naming_it() {
    let e = toml_err(&GOOD.replace("mass_kg = 0.1", "mass_kg = 0.0"));
    assert!(
        e.contains("bad.toml") && e.contains("body femur") && e.contains("mass"),
        "{e}"
    );
    assert!(e.contains("above zero"), "{e}");
}

#[test]
fn an_inertia_violating_the_triangle_inequality_is_refused() {
    // Principal moments 1e-5, 1e-5, 1e-4: 1e-5 + 1e-5 < 1e-4, no mass distribution has them.
    let e = toml_err(&GOOD.replace(
        FEMUR_INERTIA,
        "inertia_kg_m2 = [1e-5, 1e-5, 1e-4, 0.0, 0.0, 0.0]",
    ));
    assert!(
        e.contains("body femur") && e.contains("inertia") && e.contains("triangle inequality"),
        "{e}"
    );
    // A thin rod meets it with equality (0 + I = I) and is only refused for its zero moment;
    // a slightly thick one (1e-9 + 1e-4 >= 1e-4) passes.
    from_toml_str(
        &GOOD.replace(
            FEMUR_INERTIA,
            "inertia_kg_m2 = [1e-9, 1e-4, 1e-4, 0.0, 0.0, 0.0]",
        ),
        "rod.toml",
    )
    .unwrap();
}

#[test]
fn an_inertia_that_is_not_positive_definite_is_refused() {
    // Semi-definite (a zero principal moment): accepted by the TOML reader's own check before.
    let e = toml_err(&GOOD.replace(
        FEMUR_INERTIA,
        "inertia_kg_m2 = [0.0, 1e-4, 1e-4, 0.0, 0.0, 0.0]",
    ));
    assert!(
        e.contains("body femur") && e.contains("inertia") && e.contains("positive definite"),
        "{e}"
    );
}

#[test]
fn a_leg_with_joints_but_no_foot_is_said() {
    let footless = GOOD
        .split("[[foot]]")
        .next()
        .unwrap()
        .replace("name = \"one-leg\"", "name = \"one-leg\"\nfoot = []");
    let e = toml_err(&footless);
    assert!(
        e.contains("leg LF") && e.contains("foot") && e.contains("LF_CTr"),
        "{e}"
    );
    // The importer: the Drosobot II project without LF's tip body.
    let start = DROSOBOT2.find("<RigidBody><Name>LF_Tip</Name>").unwrap();
    let len = DROSOBOT2[start..].find("</RigidBody>").unwrap() + "</RigidBody>".len();
    let tipless = format!("{}{}", &DROSOBOT2[..start], &DROSOBOT2[start + len..]);
    let e = aproj_err(&tipless);
    assert!(e.contains("leg LF") && e.contains("foot"), "{e}");
}

/// The servo models a model file may name are the dynamixel crate's (`ServoModel::key`); an
/// unknown one (the MX-106 the robot does not carry) is refused naming the file and the accepted
/// names, never read as a generic actuator; a servo map on a generic actuator is refused too.
#[test]
fn an_unknown_servo_model_or_a_servo_on_a_generic_actuator_is_refused() {
    let e = toml_err(&GOOD.replace(r#"actuation = "mx64""#, r#"actuation = "mx106""#));
    assert!(
        e.contains("bad.toml") && e.contains(r#"unknown actuation "mx106""#),
        "{e}"
    );
    assert!(e.contains(r#""mx28", "mx64""#), "{e}");
    let with_servo = GOOD.replace(
        "stiffness_nm_per_rad = 30.0",
        "stiffness_nm_per_rad = 30.0\nservo = { id = 1, zero_offset_rad = 0.0, sign = 1 }",
    );
    let m = from_toml_str(&with_servo, "good.toml").unwrap();
    assert_eq!(
        m.joints[0].actuation,
        Actuation::Actuated {
            actuator: ActuatorKind::Servo(dynamixel::ServoModel::Mx64),
            stiffness: 30.0
        }
    );
    assert_eq!(m.servo_chain(), vec![(1, dynamixel::ServoModel::Mx64)]);
    let e = toml_err(&with_servo.replace(r#"actuation = "mx64""#, r#"actuation = "generic""#));
    assert!(
        e.contains("LF_CTr") && e.contains("a generic actuator has no servo"),
        "{e}"
    );
}

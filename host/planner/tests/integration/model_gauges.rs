//! Gauges in the model: the built-in Drosophibot II carries the lab's six per leg in the strain
//! board's channel order (../shared/reference/lab-practice.md: legs LH, RH, LM, RM, LF, RF; per
//! leg trochanter axial, transverse, 45 deg, femur +45, -45 deg, axial), the scale fly the same
//! sites; gauges survive a write and read of the model file; bad entries are refused naming the
//! file, the gauge and the field.

use planner::model::{GaugeDirection, builtin, from_toml_str, to_toml_string};

const BOARD_LEGS: [&str; 6] = ["LH", "RH", "LM", "RM", "LF", "RF"];
const BOARD_GAUGES: [(&str, &str, GaugeDirection); 6] = [
    ("Trochanter", "troch_axial", GaugeDirection::Axial),
    ("Trochanter", "troch_transverse", GaugeDirection::Transverse),
    ("Trochanter", "troch_45", GaugeDirection::Plus45),
    ("Femur", "femur_plus45", GaugeDirection::Plus45),
    ("Femur", "femur_minus45", GaugeDirection::Minus45),
    ("Femur", "femur_axial", GaugeDirection::Axial),
];

#[test]
fn builtin_models_carry_the_lab_gauges_in_board_order() {
    for name in ["drosophibot2", "scale-drosophila"] {
        let m = builtin(name).unwrap();
        assert_eq!(m.gauges.len(), 36, "{name}");
        for (i, g) in m.gauges.iter().enumerate() {
            let leg = BOARD_LEGS[i / 6];
            let (segment, suffix, direction) = BOARD_GAUGES[i % 6];
            assert_eq!(g.name, format!("{leg}_{suffix}"), "{name} channel {i}");
            assert_eq!(g.leg.name(), leg);
            assert_eq!(m.bodies[g.segment].name, format!("{leg}_{segment}"));
            assert_eq!(g.direction, direction);
            // The face is across the segment: perpendicular to its axis.
            let axis = m.segment_span(g.segment).unwrap().normalize();
            assert!(g.face.dot(&axis).abs() < 1e-9, "{name} {}", g.name);
        }
    }
}

#[test]
fn gauges_survive_writing_and_reading_the_model_file() {
    let m = builtin("drosophibot2").unwrap();
    let text = to_toml_string(&m, "round trip", &|_| String::new());
    let back = from_toml_str(&text, "written.toml").unwrap();
    assert_eq!(back.gauges.len(), m.gauges.len());
    for (a, b) in m.gauges.iter().zip(&back.gauges) {
        assert_eq!(a.name, b.name);
        assert_eq!(a.segment, b.segment);
        assert_eq!(a.direction, b.direction);
        assert_eq!(a.section, b.section);
        assert_eq!(a.material, b.material);
        assert!((a.position - b.position).abs() < 1e-15);
        assert!((a.face.into_inner() - b.face.into_inner()).norm() < 1e-12);
    }
}

/// The built-in model's text with its first gauge's `field = value` line replaced.
fn with_first_gauge(field: &str, value: &str) -> String {
    let text = include_str!("../../models/drosophibot2.toml");
    let start = text.find("[[gauge]]").unwrap();
    let line = text[start..]
        .lines()
        .find(|l| l.starts_with(&format!("{field} =")))
        .unwrap();
    let at = start + text[start..].find(line).unwrap();
    format!(
        "{}{field} = {value}{}",
        &text[..at],
        &text[at + line.len()..]
    )
}

fn refused(field: &str, value: &str) -> String {
    match from_toml_str(&with_first_gauge(field, value), "robot.toml") {
        Ok(_) => panic!("{field} = {value} was accepted"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn bad_gauges_are_refused_naming_the_gauge_and_the_field() {
    let cases = [
        ("segment", "\"LH_Wing\"", "unknown segment `LH_Wing`"),
        ("segment", "\"RF_Femur\"", "belongs to leg RF, not LH"),
        ("segment", "\"thorax\"", "is not a leg segment"),
        (
            "position_fraction",
            "1.5",
            "field `position_fraction`: 1.5 is beyond the segment",
        ),
        (
            "face",
            "[0.0, -1.0, 0.0]",
            "field `face`: is within 30 deg of the segment axis",
        ),
        (
            "face",
            "[0.0, 0.0, 0.0]",
            "field `face`: must be a finite non-zero vector",
        ),
        (
            "section",
            "{ shape = \"circular_tube\", outer_diameter_m = 0.02, wall_m = 0.0 }",
            "field `section.wall_m`",
        ),
        (
            "section",
            "{ shape = \"circular_tube\", outer_diameter_m = 0.0, wall_m = 0.0 }",
            "zero section",
        ),
        (
            "material",
            "{ youngs_modulus_pa = 2.4e9, poisson_ratio = 0.6 }",
            "field `material.poisson_ratio`",
        ),
    ];
    for (field, value, want) in cases {
        let e = refused(field, value);
        assert!(e.starts_with("robot.toml: gauge LH_troch_axial: "), "{e}");
        assert!(e.contains(want), "{field} = {value}: `{e}` lacks `{want}`");
    }
    let e = refused("name", "\"LH_troch_transverse\"");
    assert!(
        e.contains("gauge LH_troch_transverse: field `name`: defined twice"),
        "{e}"
    );
    let e = refused("direction", "\"sideways\"");
    assert!(e.contains("robot.toml") && e.contains("sideways"), "{e}");
}

//! The AnimatLab importer against the built-in model files, the paper's table 2, and bad input.

use crate::model_support;
use model_support::ONE_LEG as GOOD;

use planner::model::*;
use std::path::PathBuf;

fn aproj(name: &str) -> PathBuf {
    PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/models/animatlab"
    ))
    .join(name)
}

/// Geometry, mass properties, limits and which joints are actuated must agree; actuator models,
/// stiffness and servo maps are not in the .aproj (they come from the paper, see the TOML notes).
fn assert_same_structure(imported: &Model, built: &Model) {
    let tol = 1e-9;
    assert_eq!(imported.bodies.len(), built.bodies.len());
    for (a, b) in imported.bodies.iter().zip(&built.bodies) {
        assert_eq!(a.name, b.name);
        assert!(
            (a.mass - b.mass).abs() <= tol * b.mass.max(1e-12),
            "{} mass",
            a.name
        );
        assert!(
            (a.com - b.com).norm() <= 1e-12,
            "{} com {} vs {}",
            a.name,
            a.com,
            b.com
        );
        assert!(
            (a.inertia - b.inertia).norm() <= tol * b.inertia.norm().max(1e-30),
            "{} inertia",
            a.name
        );
    }
    assert_eq!(imported.joints.len(), built.joints.len());
    for (a, b) in imported.joints.iter().zip(&built.joints) {
        assert_eq!(a.name, b.name);
        assert_eq!((a.parent, a.child), (b.parent, b.child), "{}", a.name);
        assert!(
            (a.origin.translation.vector - b.origin.translation.vector).norm() <= 1e-12,
            "{} origin",
            a.name
        );
        assert!(
            a.origin.rotation.angle_to(&b.origin.rotation) <= 1e-12,
            "{} rotation",
            a.name
        );
        assert!((a.axis.into_inner() - b.axis.into_inner()).norm() <= 1e-12);
        assert!(
            (a.limits.0 - b.limits.0).abs() <= 1e-12 && (a.limits.1 - b.limits.1).abs() <= 1e-12
        );
        assert_eq!(
            matches!(a.actuation, Actuation::Actuated { .. }),
            matches!(b.actuation, Actuation::Actuated { .. }),
            "{} actuation",
            a.name
        );
    }
    assert_eq!(imported.feet.len(), built.feet.len());
    for (a, b) in imported.feet.iter().zip(&built.feet) {
        assert_eq!((a.leg, a.body), (b.leg, b.body));
        assert!((a.point - b.point).norm() <= 1e-12);
    }
}

#[test]
fn drosobot2_import_matches_builtin() {
    let imported = import_aproj_file(&aproj("Drosobot2.aproj"), &ImportOptions::default()).unwrap();
    let built = builtin("drosophibot2").unwrap();
    assert_same_structure(&imported, &built);
    // Paper section 2.4: 22 actuated DoF; 33 bodies (solver.md); MX-64 at every CTr.
    assert_eq!(built.actuated_joints().len(), 22);
    assert_eq!(built.bodies.len(), 33);
    for j in &built.joints {
        if let Actuation::Actuated { actuator, .. } = j.actuation {
            let want = if j.kind == JointKind::CTr {
                ActuatorKind::Servo(dynamixel::ServoModel::Mx64)
            } else {
                ActuatorKind::Servo(dynamixel::ServoModel::Mx28)
            };
            assert_eq!(actuator, want, "{}", j.name);
        }
    }
    let front: Vec<JointKind> = built
        .leg_chain(Leg::LF)
        .into_iter()
        .filter(|&j| built.is_actuated(j))
        .map(|j| built.joints[j].kind)
        .collect();
    assert_eq!(
        front,
        [
            JointKind::ThC1,
            JointKind::ThC3,
            JointKind::CTr,
            JointKind::TrF1,
            JointKind::FTi
        ]
    );
    let middle: Vec<JointKind> = built
        .leg_chain(Leg::RM)
        .into_iter()
        .filter(|&j| built.is_actuated(j))
        .map(|j| built.joints[j].kind)
        .collect();
    assert_eq!(middle, [JointKind::CTr, JointKind::TrF1, JointKind::FTi]);
}

#[test]
fn scale_drosophila_import_matches_builtin() {
    let imported =
        import_aproj_file(&aproj("ScaleDrosophila.aproj"), &ImportOptions::default()).unwrap();
    let built = builtin("scale-drosophila").unwrap();
    assert_same_structure(&imported, &built);
    // Paper section 2.3: six DoF per leg.
    assert_eq!(built.actuated_joints().len(), 36);
    // A fly: about a milligram (the .aproj's grams converted to kg).
    assert!(
        (0.5e-6..2e-6).contains(&built.total_mass()),
        "{}",
        built.total_mass()
    );
}

#[test]
fn typical_hexapod_imports() {
    let m = import_aproj_file(&aproj("TypicalHexapod.aproj"), &ImportOptions::default()).unwrap();
    assert_eq!(m.feet.len(), 6);
    assert_eq!(m.actuated_joints().len(), 18);
}

/// Distance between consecutive joints and to the foot, per segment, at the zero pose (mm).
fn segment_mm(m: &Model, leg: Leg, from: JointKind, to: Option<JointKind>) -> f64 {
    let q = m.mid_range_q().iter().map(|_| 0.0).collect::<Vec<_>>();
    let poses = planner::kinematics::forward(m, &q);
    let j = |k| m.joint_index(&format!("{}_{:?}", leg.name(), k)).unwrap();
    let a = poses.joint_positions[j(from)];
    let b = match to {
        Some(k) => poses.joint_positions[j(k)],
        None => poses.feet[m.feet.iter().position(|f| f.leg == leg).unwrap()],
    };
    (a - b).norm() * 1000.0
}

#[test]
fn drosophibot2_segments_within_16_percent_of_table_2() {
    use JointKind::*;
    let m = builtin("drosophibot2").unwrap();
    // Table 2, Drosophibot II column (mm): trochanter, femur, tibia, tarsus per pair; front coxa.
    let table = [
        (Leg::RH, [27.97, 100.4, 97.85, 120.0]),
        (Leg::RM, [27.97, 100.4, 97.85, 100.0]),
        (Leg::RF, [27.97, 80.00, 77.84, 69.60]),
    ];
    for (leg, want) in table {
        let got = [
            segment_mm(&m, leg, CTr, Some(TrF1)),
            segment_mm(&m, leg, TrF1, Some(FTi)),
            segment_mm(&m, leg, FTi, Some(TiTar)),
            segment_mm(&m, leg, TiTar, None),
        ];
        for (g, w) in got.iter().zip(want) {
            // Paper: "within 16% of a 140:1 Scale-Drosophila"; the model file's lengths within 16%
            // of the built robot's.
            assert!(
                (g - w).abs() / w < 0.16,
                "{leg:?}: {g:.2} mm vs table 2 {w} mm"
            );
        }
    }
    let coxa = segment_mm(&m, Leg::RF, ThC3, Some(CTr));
    assert!((coxa - 54.5).abs() / 54.5 < 0.16, "front coxa {coxa:.2} mm");
}

fn err(text: &str) -> String {
    from_toml_str(text, "bad.toml").unwrap_err().to_string()
}

#[test]
fn good_file_loads() {
    let m = from_toml_str(GOOD, "good.toml").unwrap();
    assert_eq!(m.joints[0].name, "LF_CTr");
}

#[test]
fn bad_model_files_name_file_place_and_field() {
    let e = err(&GOOD.replace("mass_kg = 0.1", "mass_kg = -0.1"));
    assert!(
        e.contains("bad.toml") && e.contains("body femur") && e.contains("mass_kg"),
        "{e}"
    );
    let e = err(&GOOD.replace("limits_rad = [-1.0, 1.0]", "limits_rad = [1.0, -1.0]"));
    assert!(
        e.contains("joint LF_CTr") && e.contains("limits_rad"),
        "{e}"
    );
    let e = err(&GOOD.replace("parent = \"thorax\"", "parent = \"abdomen\""));
    assert!(e.contains("joint LF_CTr") && e.contains("abdomen"), "{e}");
    let e = err(&GOOD.replace("stiffness_nm_per_rad = 30.0", ""));
    assert!(
        e.contains("stiffness_nm_per_rad") && e.contains("LF_CTr"),
        "{e}"
    );
    let e = err(&GOOD.replace("axis = [1.0, 0.0, 0.0]", "axis = [0.0, 0.0, 0.0]"));
    assert!(e.contains("axis"), "{e}");
    let e = err(&GOOD.replace(
        "inertia_kg_m2 = [1e-5, 1e-4, 1e-4, 0.0, 0.0, 0.0]",
        "inertia_kg_m2 = [1e-5, -1e-4, 1e-4, 0.0, 0.0, 0.0]",
    ));
    assert!(
        e.contains("body femur") && e.contains("inertia_kg_m2"),
        "{e}"
    );
    let e = err(&GOOD.replace("kind = \"CTr\"", "kind = \"Knee\""));
    assert!(e.contains("bad.toml") && e.contains("Knee"), "{e}");
    let e = err(&GOOD.replace("body = \"femur\"", "body = \"tibia\""));
    assert!(e.contains("foot LF") && e.contains("tibia"), "{e}");
    assert!(
        builtin("robot-x")
            .unwrap_err()
            .to_string()
            .contains("drosophibot2")
    );
}

#[test]
fn bad_aproj_names_the_problem() {
    let e = import_aproj(
        "<Project><Environment><MassUnits>Stones</MassUnits></Environment></Project>",
        "x.aproj",
        &ImportOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("x.aproj") && e.contains("MassUnits") && e.contains("Stones"),
        "{e}"
    );
    let e = import_aproj("<Project><unclosed>", "y.aproj", &ImportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("y.aproj"), "{e}");
}

#[test]
fn toml_round_trip_keeps_the_model() {
    let m = builtin("drosophibot2").unwrap();
    let text = to_toml_string(&m, "", &|_| String::new());
    let back = from_toml_str(&text, "rt.toml").unwrap();
    assert_same_structure(&back, &m);
}

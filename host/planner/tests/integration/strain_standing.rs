//! A one-legged robot standing still on its foot (a "pogo", balanced over the foot so the foot
//! force is its whole weight, by hand), with gauges on its horizontal femur: the section wrench
//! is the foot force moved to the section plus the weight of what hangs distal of it, and the
//! readings follow by hand. Read through the model file format, so the gauge section is too.

use crate::model_blocks;
use model_blocks::{Joint, body, foot};
use nalgebra::Vector3;
use planner::dynamics::{CycleSolution, DynamicsOptions, SliceInput, solve_cycle};
use planner::model::{Model, from_toml_str};
use planner::strain::{StrainPrediction, predict};

/// The planner's standard gravity, m/s^2 (`SliceInput::still` uses it).
const G: f64 = 9.81;

/// Thorax 2 kg (CoM at x = L1 + m1 L1 / 2M = 0.1075 m, over the foot with the legs), a yaw hip
/// (z) and a pitch hip (y) at the origin (the coxa between them 1e-12 kg: a body needs a mass, and
/// this one moves every number below by less than 1e-11 of itself), femur along +x (0.3 kg, L1 = 0.1 m, CoM at 0.05 m),
/// knee (y) at x = 0.1, tibia hanging down (0.2 kg, L2 = 0.15 m, CoM 0.075 m below the knee),
/// foot at its end. Gauges on the femur's top face (+z) at half its length, a tube of 20 mm
/// outer diameter and 2 mm wall, E = 2.4 GPa, nu = 0.39.
fn pogo_toml() -> String {
    let joint = |kind, parent, child, origin_xyz_m, axis| {
        Joint {
            leg: "LM",
            kind,
            parent,
            child,
            origin_xyz_m,
            origin_rpy_rad: [0.0; 3],
            axis,
            limit_rad: 3.0,
            actuation: "mx28",
            stiffness_nm_per_rad: 2.0,
        }
        .block()
    };
    let (z, y) = ([0.0, 0.0, 1.0], [0.0, 1.0, 0.0]);
    let gauge = |name, position_fraction: f64, direction| {
        format!(
            "[[gauge]]\nname = \"{name}\"\nleg = \"LM\"\nsegment = \"femur\"\n\
             position_fraction = {position_fraction:?}\nface = [0.0, 0.0, 1.0]\n\
             direction = \"{direction}\"\n\
             section = {{ shape = \"circular_tube\", outer_diameter_m = 0.02, wall_m = 0.002 }}\n\
             material = {{ youngs_modulus_pa = 2.4e9, poisson_ratio = 0.39 }}\n"
        )
    };
    [
        "name = \"pogo\"\n".to_string(),
        body("thorax", 2.0, [0.1075, 0.0, 0.0], [1e-6; 3]),
        body("coxa", 1e-12, [0.0; 3], [1e-18; 3]),
        body("femur", 0.3, [0.05, 0.0, 0.0], [1e-6; 3]),
        body("tibia", 0.2, [0.0, 0.0, -0.075], [1e-6; 3]),
        joint("ThC1", "thorax", "coxa", [0.0; 3], z),
        joint("CTr", "coxa", "femur", [0.0; 3], y),
        joint("FTi", "femur", "tibia", [0.1, 0.0, 0.0], y),
        foot("LM", "tibia", [0.0, 0.0, -0.15]),
        gauge("LM_femur_axial", 0.5, "axial"),
        gauge("LM_femur_transverse", 0.5, "transverse"),
        gauge("LM_femur_hip", 0.0, "axial"),
    ]
    .concat()
}

fn pogo() -> Model {
    from_toml_str(&pogo_toml(), "pogo.toml").unwrap()
}

/// The pogo standing still: its one-slice cycle and the strain it predicts.
fn standing() -> (CycleSolution, StrainPrediction) {
    let model = pogo();
    let input = SliceInput::still(&model, vec![0.0; 3]);
    let cycle = solve_cycle(
        &model,
        std::slice::from_ref(&input),
        &DynamicsOptions::default(),
    )
    .unwrap();
    let strain = predict(&model, &[input], &cycle).unwrap();
    (cycle, strain)
}

#[test]
fn standing_leg_section_wrench_is_the_foot_force_moved_to_the_section_plus_distal_weight() {
    let (cycle, strain) = standing();
    let w_total = 2.5 * G;
    assert!((cycle.slices[0].grf[0] - Vector3::new(0.0, 0.0, w_total)).norm() < 1e-9 * w_total);
    let r = strain.readings[0][0];
    // By hand, section at P = (0.05, 0, 0); distal: the tibia (0.2 kg at (0.1, 0, -0.075)) and
    // the femur's distal half (0.15 kg at (0.075, 0, 0)). Force of the distal part on the
    // proximal: the foot force plus the distal weight, (0, 0, W - 0.35 g) = (0, 0, 21.0915) N.
    // Moment about P: (0.05, 0, -0.15) x (0, 0, W) + (0.05, 0, -0.075) x (0, 0, -0.2 g)
    // + (0.025, 0, 0) x (0, 0, -0.15 g) = (0, -0.05 W + 0.01 g + 0.00375 g, 0)
    // = (0, -1.0913625, 0) N m. Section frame (a, n, t) = (+x, +z, -y).
    let fz = w_total - 0.35 * G;
    let m_t = 0.05 * w_total - 0.01375 * G;
    assert!((fz - 21.0915).abs() < 1e-12 && (m_t - 1.0913625).abs() < 1e-12);
    let want_f = Vector3::new(0.0, fz, 0.0);
    let want_m = Vector3::new(0.0, 0.0, m_t);
    assert!(
        (r.wrench.force - want_f).norm() < 1e-9,
        "force {:?} vs {want_f:?}",
        r.wrench.force
    );
    assert!(
        (r.wrench.moment - want_m).norm() < 1e-9,
        "moment {:?} vs {want_m:?}",
        r.wrench.moment
    );
    // The femur is pushed up at its end: the top face is compressed, sigma = -M_t c / I with
    // I = 4.636991e-9 m^4: -1.0913625 * 0.01 / I / 2.4e9 = -980.667 microstrain; the
    // transverse gauge -nu times that.
    assert!(
        (r.microstrain - -980.666_986).abs() < 1e-4,
        "{}",
        r.microstrain
    );
    let tr = strain.readings[0][1].microstrain;
    assert!((tr - 0.39 * 980.666_986).abs() < 1e-4, "{tr}");
}

/// At the proximal end (fraction 0) the whole femur is distal, so the section carries what the
/// hip joint carries: the joint's force and moment (parent on child) with the sign flipped.
#[test]
fn a_cut_at_the_proximal_joint_carries_the_joint_wrench() {
    let (cycle, strain) = standing();
    let r = strain.readings[0][2];
    let (jf, jm) = (
        cycle.slices[0].joint_force[1],
        cycle.slices[0].joint_moment[1],
    );
    // Section frame (+x, +z, -y).
    let frame = |v: Vector3<f64>| Vector3::new(v.x, v.z, -v.y);
    assert!((r.wrench.force + frame(jf)).norm() < 1e-9);
    assert!((r.wrench.moment + frame(jm)).norm() < 1e-9);
    // By hand, the hip moment (the pogo test's) L1 g (M + m1 / 2) = 0.1 g 2.15 about +y.
    assert!((jm.y - 0.215 * G).abs() < 1e-9, "{jm:?}");
}

//! The robot-versus-fly statistics against published and hand-computed values.

use planner::analysis::{
    DofTrace, SweepPoint, classify_sweep, compare, fit::regression_r2, resample_periodic,
};
use planner::model::{JointKind, Leg};

/// Anscombe's quartet (Anscombe 1973): all four sets have correlation 0.816, so R^2 = 0.666
/// (to three decimals), the published value.
#[test]
fn anscombe_quartet_r_squared() {
    let x = [10.0, 8.0, 13.0, 9.0, 11.0, 14.0, 6.0, 4.0, 12.0, 7.0, 5.0];
    let y1 = [
        8.04, 6.95, 7.58, 8.81, 8.33, 9.96, 7.24, 4.26, 10.84, 4.82, 5.68,
    ];
    let y2 = [
        9.14, 8.14, 8.74, 8.77, 9.26, 8.10, 6.13, 3.10, 9.13, 7.26, 4.74,
    ];
    let y3 = [
        7.46, 6.77, 12.74, 7.11, 7.81, 8.84, 6.08, 5.39, 8.15, 6.42, 5.73,
    ];
    for y in [y1, y2, y3] {
        let r2 = regression_r2(&x, &y).unwrap();
        assert!((r2.sqrt() - 0.816).abs() < 5e-4, "{r2}");
    }
    let x4 = [8.0, 8.0, 8.0, 8.0, 8.0, 8.0, 8.0, 19.0, 8.0, 8.0, 8.0];
    let y4 = [
        6.58, 5.76, 7.71, 8.84, 8.47, 7.04, 5.25, 12.50, 5.56, 7.91, 6.89,
    ];
    assert!((regression_r2(&x4, &y4).unwrap().sqrt() - 0.817).abs() < 5e-4);
}

#[test]
fn r_squared_edge_cases() {
    let x: Vec<f64> = (-5..=5).map(f64::from).collect();
    let line: Vec<f64> = x.iter().map(|v| -3.0 * v + 2.0).collect();
    assert!((regression_r2(&x, &line).unwrap() - 1.0).abs() < 1e-15);
    // A parabola symmetric about the mean of x has no linear trend at all.
    let parabola: Vec<f64> = x.iter().map(|v| v * v).collect();
    assert!(regression_r2(&x, &parabola).unwrap().abs() < 1e-15);
    assert_eq!(regression_r2(&x, &[1.0; 11]), None);
    assert_eq!(regression_r2(&x[..3], &line), None);
}

#[test]
fn periodic_resampling_interpolates_and_wraps() {
    let v = [0.0, 1.0, 2.0, 3.0];
    assert_eq!(
        resample_periodic(&v, 8),
        vec![0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 1.5]
    );
}

fn trace(leg: Leg, kind: JointKind, mobile: bool, f: impl Fn(f64) -> f64) -> DofTrace {
    let angle: Vec<f64> = (0..50)
        .map(|i| f(i as f64 / 50.0 * std::f64::consts::TAU))
        .collect();
    DofTrace {
        leg,
        kind,
        mobile,
        torque: angle.iter().map(|a| 2.0 * a).collect(),
        angle,
    }
}

#[test]
fn summed_plane_dof_is_compared_with_the_single_one() {
    // The fly elevates with ThC2 + CTr; the robot's single CTr follows their sum exactly.
    let fly = vec![
        trace(Leg::LH, JointKind::ThC2, true, |t| t.sin()),
        trace(Leg::LH, JointKind::CTr, true, |t| t.cos()),
        trace(Leg::LH, JointKind::FTi, true, |t| (2.0 * t).sin()),
    ];
    let robot = vec![
        trace(Leg::LH, JointKind::ThC2, false, |_| 0.3),
        trace(Leg::LH, JointKind::CTr, true, |t| {
            0.5 * (t.sin() + t.cos()) + 1.0
        }),
        trace(Leg::LH, JointKind::FTi, true, |t| (2.0 * t).sin()),
    ];
    let rows = compare(&fly, &robot);
    let get = |dof: &str| rows.iter().find(|r| r.dof == dof).unwrap();
    assert!((get("ThC2+CTr").r2_angle.unwrap() - 1.0).abs() < 1e-12);
    assert_eq!(get("ThC2+CTr").summed_side, Some(0));
    // CTr alone (cos vs sin + cos) correlates 1/sqrt 2: R^2 = 0.5.
    assert!((get("CTr").r2_angle.unwrap() - 0.5).abs() < 1e-9);
    assert!((get("FTi").r2_torque.unwrap() - 1.0).abs() < 1e-12);
    assert!(
        rows.iter().all(|r| r.dof != "ThC2"),
        "ThC2 is fixed on the robot: not a common DoF"
    );
}

#[test]
fn sweep_recognises_inertial_scaling() {
    // Inertial torque ~ 1/T^2 on top of a constant gravity torque of 1 N m.
    let points: Vec<SweepPoint> = [0.5, 1.0, 2.0, 4.0]
        .iter()
        .map(|&t| SweepPoint {
            period: t,
            peak_torque: 1.0 + 0.4 / (t * t),
            peak_inertial_torque: 0.4 / (t * t),
        })
        .collect();
    let r = classify_sweep(&points).unwrap();
    assert!((r.inertial_exponent + 2.0).abs() < 1e-12);
    assert!((r.inertial_share[3] - 0.025 / 1.025).abs() < 1e-12);
}

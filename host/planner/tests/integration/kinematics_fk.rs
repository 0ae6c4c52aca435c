//! Forward kinematics against a hand calculation, leg Jacobians against finite differences, and
//! the URDF export against an independent chain walk of the parsed URDF (urdf-rs).

use crate::model_blocks;
use model_blocks::{Joint, body, foot};
use nalgebra::{Isometry3, Point3, Rotation3, Translation3, UnitQuaternion, Vector3};
use planner::kinematics::{LegChain, forward, leg_jacobian};
use planner::model::*;
use std::collections::HashMap;

/// Thorax; femur on LF's CTr (x axis, an MX-64 at 30 N m/rad) at (0.1, 0.05, 0); tibia on FTi
/// (z axis, turned pi/2 about z, an MX-28 at 15 N m/rad) at (0, 0.1, 0) on the femur; the foot
/// at (0.2, 0, 0) on the tibia.
fn two_joints() -> String {
    let joint = |kind, parent, child, origin_xyz_m, origin_rpy_rad, axis, actuation, k| {
        Joint {
            leg: "LF",
            kind,
            parent,
            child,
            origin_xyz_m,
            origin_rpy_rad,
            axis,
            limit_rad: 2.0,
            actuation,
            stiffness_nm_per_rad: k,
        }
        .block()
    };
    [
        "name = \"two-joint\"\n".to_string(),
        body("thorax", 1.0, [0.0; 3], [1e-3, 1e-3, 1e-3]),
        body("femur", 0.1, [0.0, 0.05, 0.0], [1e-4, 1e-5, 1e-4]),
        body("tibia", 0.1, [0.1, 0.0, 0.0], [1e-5, 1e-4, 1e-4]),
        joint(
            "CTr",
            "thorax",
            "femur",
            [0.1, 0.05, 0.0],
            [0.0; 3],
            [1.0, 0.0, 0.0],
            "mx64",
            30.0,
        ),
        joint(
            "FTi",
            "femur",
            "tibia",
            [0.0, 0.1, 0.0],
            [0.0, 0.0, std::f64::consts::FRAC_PI_2],
            [0.0, 0.0, 1.0],
            "mx28",
            15.0,
        ),
        foot("LF", "tibia", [0.2, 0.0, 0.0]),
    ]
    .concat()
}

#[test]
fn fk_matches_hand_calculation() {
    let m = from_toml_str(&two_joints(), "two.toml").unwrap();
    let (t1, t2) = (std::f64::consts::FRAC_PI_2, std::f64::consts::FRAC_PI_6);
    let p = forward(&m, &[t1, t2]);
    // By hand: foot = (0.1, 0.05, 0) + Rx(t1) [(0, 0.1, 0) + Rz(pi/2 + t2) (0.2, 0, 0)]
    //               = (0.1, 0.05, 0) + Rx(pi/2) (-0.2 sin t2, 0.1 + 0.2 cos t2, 0)
    //               = (0.1 - 0.1, 0.05, 0.1 + 0.2 cos(pi/6)) = (0, 0.05, 0.273205...)
    let want = Vector3::new(0.0, 0.05, 0.1 + 0.2 * (3f64).sqrt() / 2.0);
    assert!((p.feet[0].coords - want).norm() < 1e-15, "{}", p.feet[0]);
    // The knee sits at (0.1, 0.05, 0) + Rx(pi/2)(0, 0.1, 0) = (0.1, 0.05, 0.1); its axis z turned
    // by Rx(pi/2) becomes -y.
    assert!((p.joint_positions[1].coords - Vector3::new(0.1, 0.05, 0.1)).norm() < 1e-15);
    assert!((p.joint_axes[1].into_inner() - Vector3::new(0.0, -1.0, 0.0)).norm() < 1e-15);
}

#[test]
fn jacobians_match_finite_differences() {
    for name in BUILTIN_NAMES {
        let m = builtin(name).unwrap();
        let q0 = m.mid_range_q();
        let poses = forward(&m, &q0);
        for leg in m.legs() {
            let (joints, jac) = leg_jacobian(&m, &poses, leg);
            let chain = LegChain::new(&m, leg).unwrap();
            assert_eq!(joints, chain.actuated);
            let fi = m.feet.iter().position(|f| f.leg == leg).unwrap();
            let h = 1e-7;
            for (k, &j) in joints.iter().enumerate() {
                let (mut qp, mut qm) = (q0.clone(), q0.clone());
                qp[j] += h;
                qm[j] -= h;
                let fd = (forward(&m, &qp).feet[fi] - forward(&m, &qm).feet[fi]) / (2.0 * h);
                let scale = m.leg_length(leg);
                assert!(
                    (fd - jac.column(k)).norm() < 1e-6 * scale,
                    "{name} {leg:?} joint {j}"
                );
                let qa: Vec<f64> = chain.actuated.iter().map(|&i| q0[i]).collect();
                assert!((chain.jacobian(&qa).1[k] - jac.column(k)).norm() < 1e-12 * scale);
            }
        }
    }
}

/// Walks the parsed URDF from `thorax` with plain transforms: `T(xyz) RPY(rpy) R(axis, q)`.
fn urdf_link_positions(
    robot: &urdf_rs::Robot,
    q: &HashMap<String, f64>,
) -> HashMap<String, Point3<f64>> {
    let mut pose: HashMap<String, Isometry3<f64>> =
        HashMap::from([("thorax".to_string(), Isometry3::identity())]);
    let mut pending: Vec<&urdf_rs::Joint> = robot.joints.iter().collect();
    while !pending.is_empty() {
        let before = pending.len();
        pending.retain(|j| {
            let Some(parent) = pose.get(&j.parent.link).copied() else {
                return true;
            };
            let [x, y, z] = *j.origin.xyz;
            let [r, p, yw] = *j.origin.rpy;
            let origin = Isometry3::from_parts(
                Translation3::new(x, y, z),
                UnitQuaternion::from_rotation_matrix(&Rotation3::from_euler_angles(r, p, yw)),
            );
            let motion = match j.joint_type {
                urdf_rs::JointType::Revolute => {
                    let a = Vector3::from(*j.axis.xyz);
                    UnitQuaternion::from_axis_angle(&nalgebra::Unit::new_normalize(a), q[&j.name])
                }
                _ => UnitQuaternion::identity(),
            };
            pose.insert(j.child.link.clone(), parent * origin * motion);
            false
        });
        assert!(
            pending.len() < before,
            "URDF tree does not hang from thorax"
        );
    }
    pose.into_iter()
        .map(|(k, v)| (k, Point3::from(v.translation.vector)))
        .collect()
}

#[test]
fn urdf_parses_and_its_chain_gives_our_feet() {
    for name in BUILTIN_NAMES {
        let m = builtin(name).unwrap();
        let robot = urdf_rs::read_from_string(&to_urdf(&m)).unwrap();
        assert_eq!(robot.links.iter().filter(|l| l.name == "thorax").count(), 1);
        // Every model joint is there by name, fixed ones as fixed.
        for j in &m.joints {
            let u = robot
                .joints
                .iter()
                .find(|u| u.name == j.name)
                .unwrap_or_else(|| panic!("{}", j.name));
            let fixed = matches!(j.actuation, Actuation::Fixed { .. });
            assert_eq!(
                matches!(u.joint_type, urdf_rs::JointType::Fixed),
                fixed,
                "{}",
                j.name
            );
        }
        let total: f64 = robot.links.iter().map(|l| l.inertial.mass.value).sum();
        assert!((total - m.total_mass()).abs() <= 1e-12 * m.total_mass());
        // A non-trivial pose: mid-range plus a different offset per joint.
        let q: Vec<f64> = m
            .mid_range_q()
            .iter()
            .enumerate()
            .map(|(i, v)| v + 0.05 * ((i % 5) as f64 - 2.0))
            .collect();
        let ours = forward(&m, &q);
        let qmap: HashMap<String, f64> = m
            .joints
            .iter()
            .zip(&q)
            .map(|(j, v)| (j.name.clone(), *v))
            .collect();
        let theirs = urdf_link_positions(&robot, &qmap);
        for (f, p) in m.feet.iter().zip(&ours.feet) {
            let tip = theirs[&format!("{}_tip", f.leg.name())];
            assert!(
                (tip - p).norm() < 1e-6 * m.leg_length(f.leg),
                "{name} {:?}: {tip} vs {p}",
                f.leg
            );
        }
    }
}

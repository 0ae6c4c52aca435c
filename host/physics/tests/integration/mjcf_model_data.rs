//! MuJoCo's own model data for the exported MJCF equal the model's: body masses, centres of mass
//! and inertia tensors (rebuilt from MuJoCo's principal axes), hinge axes and limits, actuator
//! gains and force limits, parallel springs. (The pytest host/physics/tests/test_mjcf.py checks
//! the same file with the Python `mujoco` package against the TOML read by Python's tomllib.)

use mujoco_rs::prelude::*;
use mujoco_rs::wrappers::mj_model::MjtObjBase;
use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};
use planner::model::{Actuation, MjcfOptions, Model, builtin, to_mjcf};

fn load(model: &Model, scene: &str) -> MjModel {
    let xml = to_mjcf(
        model,
        &MjcfOptions::stance(model, &planner::terrain::Ground::parse(scene).unwrap()).unwrap(),
    );
    MjModel::from_xml_string(&xml).unwrap_or_else(|e| panic!("{} on {scene}: {e}", model.name))
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs()))
}

#[test]
fn drosophibot_bodies_joints_and_actuators_as_mujoco_reads_them() {
    let model = builtin("drosophibot2").unwrap();
    for scene in ["flat", "incline:10", "ball", "ball-fixed"] {
        let mj = load(&model, scene);
        for b in &model.bodies {
            let id = mj.name_to_id(MjtObjBase::mjOBJ_BODY, &b.name).unwrap();
            assert!(close(mj.body_mass()[id], b.mass, 1e-12), "{}: mass", b.name);
            let ipos = Vector3::from(mj.body_ipos()[id]);
            assert!(
                (ipos - b.com).norm() < 1e-12,
                "{}: com {ipos} vs {}",
                b.name,
                b.com
            );
            // MuJoCo keeps principal moments in a rotated frame: R diag(I) R^T is the tensor.
            let [w, x, y, z] = mj.body_iquat()[id];
            let r = UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z));
            let d = Matrix3::from_diagonal(&Vector3::from(mj.body_inertia()[id]));
            let tensor =
                r.to_rotation_matrix().matrix() * d * r.to_rotation_matrix().matrix().transpose();
            let scale = b.inertia.norm();
            assert!(
                (tensor - b.inertia).norm() <= 1e-9 * scale,
                "{}: inertia\n{tensor}\nvs\n{}",
                b.name,
                b.inertia
            );
        }
        let mut hinges = 0;
        for j in &model.joints {
            let jid = mj.name_to_id(MjtObjBase::mjOBJ_JOINT, &j.name);
            let Actuation::Actuated { stiffness, .. } = j.actuation else {
                assert!(jid.is_none(), "{}: a fixed joint must not move", j.name);
                continue;
            };
            hinges += 1;
            let jid = jid.unwrap_or_else(|| panic!("{}: no hinge", j.name));
            let axis = Vector3::from(mj.jnt_axis()[jid]);
            assert!(
                (axis - j.axis.into_inner()).norm() < 1e-12,
                "{}: axis",
                j.name
            );
            let [lo, hi] = mj.jnt_range()[jid];
            assert!(
                close(lo, j.limits.0, 1e-12) && close(hi, j.limits.1, 1e-12),
                "{}: limits",
                j.name
            );
            assert!(mj.jnt_limited()[jid], "{}: limits must be on", j.name);
            let aid = mj.name_to_id(MjtObjBase::mjOBJ_ACTUATOR, &j.name).unwrap();
            assert!(
                close(mj.actuator_gainprm()[aid][0], stiffness, 1e-12),
                "{}: kp",
                j.name
            );
            // The MJCF's servo: stall torque from the e-manual, MX-28 2.5 N m, MX-64 6.0 N m.
            let stall = match j.servo.map(|s| s.model) {
                Some(dynamixel::ServoModel::Mx64) => 6.0,
                Some(dynamixel::ServoModel::Mx28) => 2.5,
                None => panic!("{}: every joint of Drosophibot II has a servo", j.name),
            };
            assert_eq!(mj.actuator_forcerange()[aid], [-stall, stall], "{}", j.name);
            let spring = j.spring.map_or(0.0, |s| s.stiffness);
            assert!(
                close(mj.jnt_stiffness()[jid], spring, 1e-12),
                "{}: spring",
                j.name
            );
        }
        assert_eq!(hinges, 22, "Drosophibot II has 22 actuated joints");
        assert_eq!(mj.ffi().nu, 22);
    }
}

#[test]
fn the_fly_model_loads_with_its_massless_bridges_raised_to_mujocos_floor() {
    let model = builtin("scale-drosophila").unwrap();
    let mj = load(&model, "flat");
    for b in &model.bodies {
        let id = mj.name_to_id(MjtObjBase::mjOBJ_BODY, &b.name).unwrap();
        let want = b.mass.max(planner::model::MUJOCO_FLOOR);
        assert!(
            close(mj.body_mass()[id], want, 1e-12),
            "{}: {} vs {}",
            b.name,
            mj.body_mass()[id],
            want
        );
    }
}

#[test]
fn a_parallel_spring_becomes_the_hinges_stiffness_and_spring_reference() {
    // Drosophibot II has no springs; give one joint a 2 N m/rad spring resting at 0.3 rad.
    let mut model = builtin("drosophibot2").unwrap();
    let j = model.joint_index("LM_FTi").unwrap();
    model.joints[j].spring = Some(planner::model::ParallelSpring {
        stiffness: 2.0,
        equilibrium: 0.3,
        equilibrium_from: planner::model::EquilibriumSource::Given,
    });
    let mj = load(&model, "flat");
    let jid = mj.name_to_id(MjtObjBase::mjOBJ_JOINT, "LM_FTi").unwrap();
    assert_eq!(mj.jnt_stiffness()[jid], 2.0);
    assert_eq!(mj.qpos_spring()[mj.jnt_qposadr()[jid] as usize], 0.3);
}

//! Test fixtures for the dynamics tests: toy organisms built in code through the shared `Model`
//! type, smooth joint trajectories with analytic derivatives, and an independent rigid-body
//! dynamics implementation (spatial-vector recursive Newton-Euler, Featherstone's formulation in
//! body coordinates) that shares no code with `planner::dynamics`.

#![allow(dead_code)]

pub mod rnea;

use nalgebra::{Isometry3, Matrix3, Translation3, UnitQuaternion, Vector3};
use planner::model::{
    Actuation, ActuatorKind, Body, EquilibriumSource, Foot, Joint, JointKind, Leg, Model,
    ParallelSpring,
};

/// Inertia of a thin rod of `mass` and `length` along local x (plus a small radial part).
pub fn rod(mass: f64, length: f64) -> Matrix3<f64> {
    let r = 0.01;
    Matrix3::from_diagonal(&Vector3::new(
        0.5 * mass * r * r,
        mass * length * length / 12.0,
        mass * length * length / 12.0 + 1e-6 * mass,
    ))
}

fn body(name: &str, mass: f64, com: Vector3<f64>, inertia: Matrix3<f64>) -> Body {
    Body {
        name: name.into(),
        mass,
        com,
        inertia,
    }
}

fn actuated(stiffness: f64) -> Actuation {
    Actuation::Actuated {
        actuator: ActuatorKind::Servo(dynamixel::ServoModel::Mx28),
        stiffness,
    }
}

/// Joint kind, joint origin, axis, mass, length, actuation of one leg segment.
type Segment = (JointKind, Isometry3<f64>, Vector3<f64>, f64, f64, Actuation);

/// A hexapod toy: box thorax (1.5 kg) and six legs with ThC1 (z), CTr (y), FTi (y) actuated and a
/// fixed TiTar, each leg's local x pointing outward. 25 bodies, 24 joints.
pub fn toy_hexapod() -> Model {
    let mut bodies = vec![Body {
        name: "thorax".into(),
        mass: 1.5,
        com: Vector3::new(-0.01, 0.0, 0.005),
        inertia: Matrix3::from_diagonal(&Vector3::new(0.004, 0.01, 0.012)),
    }];
    let mut joints = Vec::new();
    let mut feet = Vec::new();
    let hips = [0.12, 0.0, -0.12];
    for (li, leg) in Leg::ALL.iter().enumerate() {
        let side = leg.side();
        let hip = Vector3::new(hips[li % 3], side * 0.06, 0.0);
        let yaw =
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), side * std::f64::consts::FRAC_PI_2);
        let segs: [Segment; 4] = [
            (
                JointKind::ThC1,
                Isometry3::from_parts(Translation3::from(hip), yaw),
                Vector3::z(),
                0.05,
                0.03,
                actuated(4.0),
            ),
            (
                JointKind::CTr,
                Isometry3::translation(0.03, 0.0, 0.0),
                Vector3::y(),
                0.12,
                0.10,
                actuated(5.0),
            ),
            (
                JointKind::FTi,
                Isometry3::translation(0.10, 0.0, 0.0),
                Vector3::y(),
                0.08,
                0.10,
                actuated(3.0),
            ),
            (
                JointKind::TiTar,
                Isometry3::translation(0.10, 0.0, 0.0),
                Vector3::y(),
                0.02,
                0.05,
                Actuation::Fixed { angle: 0.3 },
            ),
        ];
        let mut parent = 0;
        for (kind, origin, axis, mass, length, actuation) in segs {
            let child = bodies.len();
            bodies.push(body(
                &format!("{}_{kind:?}", leg.name()),
                mass,
                Vector3::new(length / 2.0, 0.0, 0.002),
                rod(mass, length),
            ));
            joints.push(Joint {
                name: format!("{}_{kind:?}", leg.name()),
                leg: *leg,
                kind,
                parent,
                child,
                origin,
                axis: nalgebra::Unit::new_normalize(axis),
                limits: (-3.0, 3.0),
                actuation,
                spring: None,
                servo: None,
            });
            parent = child;
        }
        feet.push(Foot {
            leg: *leg,
            body: parent,
            point: Vector3::new(0.05, 0.0, 0.0),
        });
    }
    Model::of_parts("toy hexapod".into(), bodies, joints, feet)
}

/// Standing pose of the toy hexapod: coxa straight, femur raised 0.3 rad, tibia down.
pub fn standing_pose(model: &Model) -> Vec<f64> {
    model
        .joints
        .iter()
        .map(|j| match j.kind {
            JointKind::ThC1 => 0.1 * j.leg.side(),
            JointKind::CTr => -0.3,
            JointKind::FTi => 1.6,
            _ => 0.3,
        })
        .collect()
}

/// A smooth trajectory around `q0`: q = q0 + a sin(w t + phase_j), with analytic derivatives.
/// Fixed joints keep their angle.
pub fn trajectory(model: &Model, q0: &[f64], t: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut q = Vec::new();
    let mut qd = Vec::new();
    let mut qdd = Vec::new();
    for (j, joint) in model.joints.iter().enumerate() {
        if matches!(joint.actuation, Actuation::Fixed { .. }) {
            q.push(q0[j]);
            qd.push(0.0);
            qdd.push(0.0);
            continue;
        }
        let (a, w, ph) = (0.2, 2.0 * std::f64::consts::PI * 1.3, 0.7 * j as f64);
        q.push(q0[j] + a * (w * t + ph).sin());
        qd.push(a * w * (w * t + ph).cos());
        qdd.push(-a * w * w * (w * t + ph).sin());
    }
    (q, qd, qdd)
}

/// Add a parallel spring to every actuated joint.
pub fn with_springs(mut model: Model, stiffness: f64, equilibrium: f64) -> Model {
    for j in &mut model.joints {
        if matches!(j.actuation, Actuation::Actuated { .. }) {
            j.spring = Some(ParallelSpring {
                stiffness,
                equilibrium,
                equilibrium_from: EquilibriumSource::Given,
            });
        }
    }
    model
}

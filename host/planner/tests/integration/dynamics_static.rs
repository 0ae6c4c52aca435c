//! Hand-computed static poses: a one-legged "pogo" balanced over its foot (floating base) and a
//! horizontal leg on a fixed stand, with and without a parallel spring.

use nalgebra::{Isometry3, Matrix3, Unit, Vector3};
use planner::dynamics::{Base, DynamicsOptions, SliceInput, SliceSolution, solve_slice};
use planner::model::{
    Actuation, ActuatorKind, Body, EquilibriumSource, Foot, Joint, JointKind, Leg, Model,
    ParallelSpring,
};

/// The planner's standard gravity, m/s^2 (`SliceInput::still` uses it).
const G: f64 = 9.81;

fn joint(
    name: &str,
    kind: JointKind,
    parent: usize,
    child: usize,
    origin: Isometry3<f64>,
    axis: Vector3<f64>,
) -> Joint {
    Joint {
        name: name.into(),
        leg: Leg::LM,
        kind,
        parent,
        child,
        origin,
        axis: Unit::new_normalize(axis),
        limits: (-3.0, 3.0),
        actuation: Actuation::Actuated {
            actuator: ActuatorKind::Servo(dynamixel::ServoModel::Mx28),
            stiffness: 2.0,
        },
        spring: None,
        servo: None,
    }
}

fn point_body(name: &str, mass: f64, com: Vector3<f64>) -> Body {
    Body {
        name: name.into(),
        mass,
        com,
        inertia: Matrix3::identity() * 1e-6,
    }
}

/// Thorax (M) - yaw joint (z) at the origin - hip pitch (y) - femur along +x (L1, m1, CoM at
/// L1/2) - knee pitch (y) at x = L1 - tibia hanging down (L2, m2, CoM at L2/2 below the knee) - foot.
/// The thorax CoM sits at x = L1 + m1 L1 / (2 M) so that the whole CoM is over the foot.
fn pogo(big_m: f64, m1: f64, m2: f64, l1: f64, l2: f64) -> Model {
    let xc = l1 + m1 * l1 / (2.0 * big_m);
    Model {
        name: "pogo".into(),
        bodies: vec![
            point_body("thorax", big_m, Vector3::new(xc, 0.0, 0.0)),
            point_body("coxa", 0.0, Vector3::zeros()),
            point_body("femur", m1, Vector3::new(l1 / 2.0, 0.0, 0.0)),
            point_body("tibia", m2, Vector3::new(0.0, 0.0, -l2 / 2.0)),
        ],
        joints: vec![
            joint(
                "LM_ThC1",
                JointKind::ThC1,
                0,
                1,
                Isometry3::identity(),
                Vector3::z(),
            ),
            joint(
                "LM_CTr",
                JointKind::CTr,
                1,
                2,
                Isometry3::identity(),
                Vector3::y(),
            ),
            joint(
                "LM_FTi",
                JointKind::FTi,
                2,
                3,
                Isometry3::translation(l1, 0.0, 0.0),
                Vector3::y(),
            ),
        ],
        feet: vec![Foot {
            leg: Leg::LM,
            body: 3,
            point: Vector3::new(0.0, 0.0, -l2),
        }],
        gauges: Vec::new(),
        servo_dynamics: Default::default(),
        calibration: None,
        foot_friction: None,
    }
}

#[test]
fn pogo_balanced_over_its_foot() {
    let (big_m, m1, m2, l1, l2) = (2.0, 0.3, 0.2, 0.1, 0.15);
    let model = pogo(big_m, m1, m2, l1, l2);
    let s = solve_slice(
        &model,
        &SliceInput::still(&model, vec![0.0; 3]),
        &DynamicsOptions::default(),
        0,
    )
    .unwrap();
    // By hand: the foot carries the whole weight straight up.
    let w = (big_m + m1 + m2) * G;
    assert!((s.grf[0] - Vector3::new(0.0, 0.0, w)).norm() < 1e-9 * w);
    // Hip: the leg (femur + tibia) is held by the hip moment n with
    // n + (L1,0,-L2) x (0,0,W) + (L1/2,0,0) x (0,0,-m1 g) + (L1,0,-L2/2) x (0,0,-m2 g) = 0
    // => n_y = L1 W - m1 g L1/2 - m2 g L1 = L1 g (M + m1/2).
    let hip = l1 * G * (big_m + m1 / 2.0);
    // Yaw: all moments are about y, so zero. Knee: foot force and tibia weight act along the tibia.
    let expected = [0.0, hip, 0.0];
    for (j, e) in expected.iter().enumerate() {
        assert!(
            (s.torque[j] - e).abs() < 1e-9 * hip,
            "{}: {} vs {e}",
            model.joints[j].name,
            s.torque[j]
        );
    }
    // V* = 1/2 hip^2 / k with k = 2 N m/rad.
    assert!((s.v_star - 0.5 * hip * hip / 2.0).abs() < 1e-9 * s.v_star);
}

/// A horizontal leg on a fixed stand, foot in the air: the stand and joints carry gravity.
fn arm(spring: Option<ParallelSpring>) -> Model {
    let mut m = pogo(1.0, 0.3, 0.2, 0.1, 0.15);
    // Straighten: the tibia continues along +x instead of hanging.
    m.bodies[3].com = Vector3::new(0.075, 0.0, 0.0);
    m.feet[0].point = Vector3::new(0.15, 0.0, 0.0);
    for j in &mut m.joints {
        j.spring = spring;
    }
    m
}

/// One still slice of `model` at `q` on a fixed base (the stand), the foot in the air.
fn on_the_stand(model: &Model, q: Vec<f64>) -> (SliceInput, SliceSolution) {
    let mut input = SliceInput::still(model, q);
    input.stance = vec![false];
    let options = DynamicsOptions {
        base: Base::Fixed,
        ..Default::default()
    };
    let s = solve_slice(model, &input, &options, 0).unwrap();
    (input, s)
}

#[test]
fn horizontal_leg_on_a_stand_carries_its_weight() {
    let model = arm(None);
    let (_, s) = on_the_stand(&model, vec![0.0; 3]);
    // Hip about +y: to hold a mass at +x against gravity the parent pushes with moment
    // n_y = -(x m g): r x F with r = (x,0,0), F = (0,0,-m g) is (0, x m g, 0); n cancels it.
    let (m1, m2, l1) = (0.3, 0.2, 0.1);
    let hip = -(m1 * G * l1 / 2.0 + m2 * G * (l1 + 0.075));
    let knee = -(m2 * G * 0.075);
    assert!(
        (s.torque[1] - hip).abs() < 1e-12,
        "hip {} vs {hip}",
        s.torque[1]
    );
    assert!(
        (s.torque[2] - knee).abs() < 1e-12,
        "knee {} vs {knee}",
        s.torque[2]
    );
    assert!(s.torque[0].abs() < 1e-12);
    assert_eq!(s.grf[0], Vector3::zeros());
    // The stand takes the whole weight (thorax 1 kg + leg).
    assert!((s.base_force - Vector3::new(0.0, 0.0, (1.0 + m1 + m2) * G)).norm() < 1e-12);
}

/// A parallel spring of 0.5 N m/rad resting at 0.4 rad, on every joint of the arm.
const SPRING: ParallelSpring = ParallelSpring {
    stiffness: 0.5,
    equilibrium: 0.4,
    equilibrium_from: EquilibriumSource::Given,
};

#[test]
fn parallel_spring_takes_part_of_the_torque() {
    // Spring torque -k_s (q - q_eq) = -0.5 (0 - 0.4) = +0.2 N m on every joint: the actuator
    // supplies the total axis moment minus that.
    let model = arm(Some(SPRING));
    let (_, s) = on_the_stand(&model, vec![0.0; 3]);
    let hip = -(0.3 * G * 0.05 + 0.2 * G * 0.175);
    assert!((s.spring_torque[1] - 0.2).abs() < 1e-15);
    assert!((s.axis_moment[1] - hip).abs() < 1e-12);
    assert!((s.torque[1] - (hip - 0.2)).abs() < 1e-12);
    // V* uses k = actuator 2.0 + spring 0.5.
    let expected: f64 = s.torque.iter().map(|t| 0.5 * t * t / 2.5).sum();
    assert!((s.v_star - expected).abs() < 1e-15);
}

#[test]
fn servo_command_bias_is_torque_over_servo_stiffness() {
    // Paper section 2.5: command = planned angle + torque / servo stiffness. The spring does not
    // enter: with a spring the actuator torque is smaller, and so is the bias.
    let model = arm(Some(SPRING));
    let (input, s) = on_the_stand(&model, vec![0.1, -0.2, 0.3]);
    let cmd = planner::dynamics::output::biased_commands(&model, &input.q, &s.torque);
    // Servo stiffness of every joint of the arm is 2.0 N m/rad.
    for ((c, q), t) in cmd.iter().zip(&input.q).zip(&s.torque) {
        assert!((c - (q + t / 2.0)).abs() < 1e-15);
    }
    // Hip holds the straight leg: the bias lowers the command by |T| / k in the direction of the torque.
    assert!(s.torque[1] < 0.0 && cmd[1] < input.q[1]);
}

//! Standing still on flat ground: MuJoCo against a physical law (the feet carry the weight) and
//! against the planner (the servo torques of the same stance).
//!
//! Why the torques agree closely but not exactly: the planner's V* optimum is the statically
//! admissible torque set of least elastic energy, which is the elastic equilibrium of compliant
//! joints only if the feet were pinned while the structure was unstressed. Here the feet touch
//! down while gravity ramps in and the joints still move toward their goals, and stick there
//! (no-slip), so some internal force between the feet stays locked in; the contact spheres also
//! touch the ground 5 mm below their centres rather than at a point, and the body sags by
//! torque / stiffness where the bias does not cancel it. Measured at the physics robot's 1 ms
//! (`cargo nextest run -p physics -E 'test(/^standing::/)' --no-capture` prints them): 3.25 % RMS of the
//! planned torques with the bias, worst joint 0.0241 N m (LF_ThC1, a small torque), angles within
//! 1.69 mrad; the feet carry the weight to 1e-8 (49.0559 N), on a 10 degree incline m g cos to
//! 1e-9. (At 0.5 ms: 3.3 %, 0.024 N m, 1.6 mrad.)

use physics::{PhysicsRobot, Plant};
use planner::dynamics::{DynamicsOptions, SliceInput, solve_slice};
use planner::model::builtin;
use planner::terrain::Ground;

struct Stance {
    plant: Plant,
    planned: Vec<f64>,
    q: Vec<f64>,
}

/// Holds the planner's resting posture for `seconds` (gravity ramps in over the first second)
/// with goals `q + bias * tau / k`, the firmware's torque bias when `bias` is 1.
fn stand(bias: f64, seconds: f64) -> Stance {
    stand_on("flat", bias, seconds)
}

fn stand_on(scene: &str, bias: f64, seconds: f64) -> Stance {
    let model = builtin("drosophibot2").unwrap();
    let options = PhysicsRobot::options(&model, &Ground::parse(scene).unwrap()).unwrap();
    let q = options.stance_q.clone();
    let still = SliceInput::still(&model, q.clone());
    let planned = solve_slice(&model, &still, &DynamicsOptions::default(), 0)
        .unwrap()
        .torque;
    let mut plant = Plant::new(&model, &options).unwrap();
    for i in 0..plant.joints().len() {
        let j = plant.joints()[i].clone();
        plant.set_goal(i, q[j.joint] + bias * planned[j.joint] / j.kp, true);
    }
    plant.advance_to(seconds);
    Stance { plant, planned, q }
}

/// RMS of (simulated - planned) over RMS of planned, the worst joint's |difference| and its name,
/// and the largest |angle - planned angle|.
fn compare(s: &Stance) -> (f64, f64, String, f64) {
    let (mut num, mut den, mut worst, mut name, mut dq) = (0.0, 0.0, 0.0, String::new(), 0.0f64);
    for (i, j) in s.plant.joints().iter().enumerate() {
        let (angle, _, tau) = s.plant.joint_state(i);
        let d = tau - s.planned[j.joint];
        num += d * d;
        den += s.planned[j.joint].powi(2);
        if d.abs() > worst {
            (worst, name) = (d.abs(), j.name.clone());
        }
        dq = dq.max((angle - s.q[j.joint]).abs());
    }
    ((num / den).sqrt(), worst, name, dq)
}

#[test]
fn standing_still_the_feet_carry_the_weight_within_one_percent() {
    let s = stand(1.0, 3.0);
    assert!(s.plant.full_gravity());
    let normal = s.plant.contact_normal_total();
    // Independent weight: the sum of the model file's body masses times g (5.0006 kg, 49.056 N;
    // the pytest sums the TOML itself).
    let w = s.plant.weight_n();
    assert!((w - 5.0006 * 9.81).abs() < 0.01, "weight {w}");
    eprintln!(
        "normal {normal} N, weight {w} N: {:+.4} %",
        (normal / w - 1.0) * 100.0
    );
    assert!(
        (normal - w).abs() < 0.01 * w,
        "normal {normal} N vs weight {w} N"
    );
    // All six feet down, none sliding.
    let still = s
        .plant
        .foot_forces()
        .iter()
        .filter(|(_, f)| f[2] > 0.5)
        .count();
    assert_eq!(still, 6);
}

#[test]
fn on_an_incline_the_ground_carries_the_weight_times_the_cosine() {
    // 10 degrees: the normal force is m g cos(10 deg) = 0.9848 m g, the rest is friction.
    let s = stand_on("incline:10", 1.0, 3.0);
    let want = s.plant.weight_n() * 10f64.to_radians().cos();
    let normal = s.plant.contact_normal_total();
    eprintln!("incline: normal {normal} N vs {want} N");
    assert!(
        (normal - want).abs() < 0.01 * want,
        "normal {normal} N vs {want} N"
    );
}

#[test]
fn a_static_stance_loads_the_servos_as_the_planner_says() {
    // With the torque bias the joints end at the planned angles and carry the planned torques
    // (bounds: twice the measured 3.25 % / 0.0241 N m / 1.69 mrad at 1 ms, see the header).
    let s = stand(1.0, 3.0);
    let (rel, worst, name, dq) = compare(&s);
    assert!(rel < 0.066, "relative RMS {rel}");
    assert!(worst < 0.05, "{name}: {worst} N m");
    assert!(dq < 0.0035, "angle error {dq} rad");
    // Without the bias the body sags by torque / stiffness (0.6 / 34.3 = 17 mrad at a middle CTr
    // alone, more along a chain; measured 39.2 mrad at 1 ms): the torques still follow the plan
    // (measured 3.78 % RMS), the angles do not.
    let s = stand(0.0, 3.0);
    let (rel0, _, _, dq0) = compare(&s);
    eprintln!(
        "bias off: relative RMS {rel0}, angle error {dq0} rad; bias on: {rel}, worst {name} {worst} N m, {dq} rad"
    );
    assert!(
        dq0 > 3.0 * dq,
        "the bias must buy posture: {dq0} vs {dq} rad"
    );
    assert!(rel0 < 0.08, "relative RMS without bias {rel0}");
}

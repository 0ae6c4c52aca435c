//! Whole-robot balance in every slice: sum of GRF + gravity equals the rate of change of linear
//! momentum of all bodies, and the moments about the thorax origin equal the rate of change of
//! angular momentum, with the momentum rates from the independent spatial-vector implementation
//! (and, for the force, from finite differences of the CoM positions).

use crate::dynamics_support;
use dynamics_support::rnea::{BaseState, com_positions, momentum_rate};
use dynamics_support::{standing_pose, toy_hexapod, trajectory};
use nalgebra::Vector3;
use planner::dynamics::{DynamicsOptions, SliceInput, ThoraxMotion, solve_cycle};
use planner::model::Model;

const TRIPOD_A: [bool; 6] = [true, false, true, false, true, false];

fn stance_pattern(i: usize) -> Vec<bool> {
    match i % 4 {
        0 => vec![true; 6],
        1 => TRIPOD_A.to_vec(),
        2 => TRIPOD_A.iter().map(|s| !s).collect(),
        _ => vec![true, true, false, true, false, true],
    }
}

fn slices(model: &Model, thorax: ThoraxMotion, n: usize) -> Vec<SliceInput> {
    let q0 = standing_pose(model);
    (0..n)
        .map(|i| {
            let (q, qd, qdd) = trajectory(model, &q0, i as f64 * 0.037);
            let mut s = SliceInput::still(model, q);
            s.qd = qd;
            s.qdd = qdd;
            s.stance = stance_pattern(i);
            s.thorax = thorax;
            s.gravity = Vector3::new(0.8, -0.3, -9.7);
            s
        })
        .collect()
}

fn check_balance(model: &Model, inputs: &[SliceInput], options: &DynamicsOptions) {
    let total_weight: f64 = model.bodies.iter().map(|b| b.mass).sum::<f64>() * 9.81;
    let sol = solve_cycle(model, inputs, options).unwrap();
    for (i, (s, input)) in sol.slices.iter().zip(inputs).enumerate() {
        let base = BaseState {
            omega: input.thorax.angular_velocity,
            alpha: input.thorax.angular_acceleration,
            velocity: input.thorax.linear_velocity,
            acceleration: input.thorax.linear_acceleration,
        };
        let (dp, dh) = momentum_rate(model, &input.q, &input.qd, &input.qdd, base);
        let mass: f64 = model.bodies.iter().map(|b| b.mass).sum();
        let coms = com_positions(model, &input.q);
        let force = s.grf.iter().sum::<Vector3<f64>>() + mass * input.gravity;
        let moment = s
            .grf
            .iter()
            .zip(&s.foot_position)
            .map(|(g, p)| p.cross(g))
            .sum::<Vector3<f64>>()
            + model
                .bodies
                .iter()
                .zip(&coms)
                .map(|(b, c)| c.cross(&(b.mass * input.gravity)))
                .sum::<Vector3<f64>>();
        let span = s.foot_position.iter().map(|p| p.norm()).fold(0.0, f64::max);
        assert!(
            (force - dp).norm() <= 1e-9 * total_weight,
            "slice {i}: force balance off by {:e}",
            (force - dp).norm()
        );
        assert!(
            (moment - dh).norm() <= 1e-9 * total_weight * span,
            "slice {i}: moment balance off by {:e}",
            (moment - dh).norm()
        );
        for (f, g) in s.grf.iter().enumerate() {
            if !input.stance[f] {
                assert_eq!(
                    *g,
                    Vector3::zeros(),
                    "slice {i}: swing foot {f} has GRF {g}"
                );
            }
        }
    }
}

#[test]
fn balance_with_inertial_thorax_every_stance_pattern() {
    let model = toy_hexapod();
    check_balance(
        &model,
        &slices(&model, ThoraxMotion::default(), 24),
        &DynamicsOptions::default(),
    );
}

#[test]
fn balance_with_rotating_and_accelerating_thorax() {
    let model = toy_hexapod();
    let thorax = ThoraxMotion {
        linear_velocity: Vector3::new(0.2, 0.01, 0.0),
        angular_velocity: Vector3::new(0.1, -0.2, 0.3),
        linear_acceleration: Vector3::new(0.5, -0.2, 0.1),
        angular_acceleration: Vector3::new(-0.4, 0.3, 0.2),
    };
    check_balance(
        &model,
        &slices(&model, thorax, 16),
        &DynamicsOptions::default(),
    );
}

#[test]
fn balance_with_clarabel_and_contact_constraints() {
    let model = toy_hexapod();
    let options = DynamicsOptions {
        friction_cone: true,
        mu: 0.8,
        always_clarabel: true,
        ..Default::default()
    };
    check_balance(
        &model,
        &slices(&model, ThoraxMotion::default(), 12),
        &options,
    );
    let options = DynamicsOptions {
        push_only: true,
        ..Default::default()
    };
    check_balance(
        &model,
        &slices(&model, ThoraxMotion::default(), 12),
        &options,
    );
}

/// The momentum rate by finite differences of CoM positions along the trajectory (no shared
/// acceleration formula at all): fourth-order central differences, step 1e-3 s.
#[test]
fn linear_momentum_rate_matches_finite_differences_of_com() {
    let model = toy_hexapod();
    let q0 = standing_pose(&model);
    let h = 1e-3;
    for i in 0..6 {
        let t = 0.05 + 0.1 * i as f64;
        let (q, qd, qdd) = trajectory(&model, &q0, t);
        let mut input = SliceInput::still(&model, q);
        input.qd = qd;
        input.qdd = qdd;
        let sol = solve_cycle(
            &model,
            std::slice::from_ref(&input),
            &DynamicsOptions::default(),
        )
        .unwrap();
        let com_sum = |t: f64| -> Vector3<f64> {
            let (q, _, _) = trajectory(&model, &q0, t);
            com_positions(&model, &q)
                .iter()
                .zip(&model.bodies)
                .map(|(c, b)| b.mass * c)
                .sum()
        };
        let acc = (-com_sum(t + 2.0 * h) + 16.0 * com_sum(t + h) - 30.0 * com_sum(t)
            + 16.0 * com_sum(t - h)
            - com_sum(t - 2.0 * h))
            / (12.0 * h * h);
        let mass: f64 = model.bodies.iter().map(|b| b.mass).sum();
        let force = sol.slices[0].grf.iter().sum::<Vector3<f64>>() + mass * input.gravity;
        assert!(
            (force - acc).norm() < 1e-6 * mass * 9.81,
            "t {t}: {force} vs {acc}"
        );
    }
}

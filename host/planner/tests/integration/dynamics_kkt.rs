//! Optimality of the returned solutions: the KKT conditions of the QP as posed (stationarity,
//! primal feasibility, cone membership of slacks and multipliers, complementarity), checked here
//! from the problem data; and the two solvers (direct, Clarabel) agree on the same problem.

use crate::dynamics_support;
use dynamics_support::{standing_pose, toy_hexapod, trajectory};
use planner::dynamics::{DynamicsOptions, SliceInput, slice_problem, solve_problem};
use planner::model::Model;
use planner::qp::{ConeBlock, QpProblem, QpSolution};

fn input(model: &Model, i: usize) -> SliceInput {
    let (q, qd, qdd) = trajectory(model, &standing_pose(model), 0.07 * i as f64);
    let mut s = SliceInput::still(model, q);
    s.qd = qd;
    s.qdd = qdd;
    s.stance = (0..6usize)
        .map(|f| i.is_multiple_of(3) || (f + i).is_multiple_of(2))
        .collect();
    s
}

fn check_kkt(p: &QpProblem, s: &QpSolution, tol: f64, what: &str) {
    let grad = &p.p * &s.x + &p.q + p.a.transpose() * &s.z;
    let scale = 1.0 + p.q.norm() + (&p.p * &s.x).norm();
    assert!(
        grad.norm() < tol * scale,
        "{what}: stationarity residual {:e}",
        grad.norm()
    );
    let primal = &p.a * &s.x + &s.s - &p.b;
    assert!(
        primal.norm() < 1e-12 * (1.0 + p.b.norm()),
        "{what}: primal residual {:e}",
        primal.norm()
    );
    let mut row = 0;
    for c in &p.cones {
        let k = c.rows();
        let (sv, zv) = (s.s.rows(row, k), s.z.rows(row, k));
        match c {
            ConeBlock::Zero(_) => {
                assert!(sv.norm() < 1e-12, "{what}: equality slack {:e}", sv.norm())
            }
            ConeBlock::Nonnegative(_) => {
                for i in 0..k {
                    assert!(
                        sv[i] > -tol && zv[i] > -tol,
                        "{what}: nonneg row {} s {} z {}",
                        row + i,
                        sv[i],
                        zv[i]
                    );
                    assert!(
                        (sv[i] * zv[i]).abs() < tol,
                        "{what}: complementarity row {}: {:e}",
                        row + i,
                        sv[i] * zv[i]
                    );
                }
            }
            ConeBlock::SecondOrder(_) => {
                let tail = |v: nalgebra::DVectorView<f64>| v.rows(1, k - 1).norm();
                assert!(sv[0] >= tail(sv) - tol, "{what}: slack outside cone");
                assert!(
                    zv[0] >= tail(zv) - tol,
                    "{what}: multiplier outside dual cone"
                );
                assert!(
                    sv.dot(&zv).abs() < tol,
                    "{what}: cone complementarity {:e}",
                    sv.dot(&zv)
                );
            }
        }
        row += k;
    }
}

#[test]
fn kkt_holds_for_the_paper_problem_both_solvers() {
    let model = toy_hexapod();
    for i in 0..9 {
        let inp = input(&model, i);
        let direct = DynamicsOptions::default();
        let clarabel = DynamicsOptions {
            always_clarabel: true,
            ..Default::default()
        };
        let prob = slice_problem(&model, &inp, &direct, i).unwrap();
        let a = solve_problem(&model, &prob, &direct, i).unwrap();
        let b = solve_problem(&model, &prob, &clarabel, i).unwrap();
        check_kkt(&prob.qp, &a, 1e-10, "direct");
        check_kkt(&prob.qp, &b, 1e-7, "clarabel");
        assert!(
            (&a.x - &b.x).norm() < 1e-6 * (1.0 + a.x.norm()),
            "slice {i}: solvers disagree"
        );
        assert_eq!(
            a.iterations, 0,
            "equality-only problems are solved directly by default"
        );
    }
}

#[test]
fn kkt_holds_with_friction_cones_and_torque_limits() {
    let model = toy_hexapod();
    let mut active = 0;
    for i in 0..9 {
        let inp = input(&model, i);
        let opts = DynamicsOptions {
            friction_cone: true,
            mu: 0.3,
            enforce_torque_limits: true,
            torque_limits: planner::dynamics::TorqueLimits::PerJoint(vec![
                Some(2.0);
                model.joints.len()
            ]),
            ..Default::default()
        };
        let prob = slice_problem(&model, &inp, &opts, i).unwrap();
        let s = solve_problem(&model, &prob, &opts, i).unwrap();
        check_kkt(&prob.qp, &s, 1e-7, "cones");
        // Count constraints that bind (multiplier clearly positive) so the test exercises them.
        active += s.z.iter().skip(6).filter(|z| **z > 1e-6).count();
    }
    assert!(
        active > 0,
        "no inequality was active; the test would not exercise the cones"
    );
}

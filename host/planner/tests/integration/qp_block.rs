//! The block-diagonal fast path of `qp::solve` (Cholesky of the per-foot blocks of P and a Schur
//! complement on the equality rows) against the general null-space path: same answers on every
//! slice of the built-in model's step cycle, a hand-solved problem, and fallback when P couples
//! blocks or the equality rows are dependent.

use nalgebra::{DMatrix, DVector};
use planner::dynamics::{DynamicsOptions, plan_inputs, slice_problem};
use planner::qp::{self, Backend, ConeBlock, QpProblem, QpSolution};

fn rel(a: &DVector<f64>, b: &DVector<f64>) -> f64 {
    (a - b).amax() / b.amax().max(f64::MIN_POSITIVE)
}

/// Stationarity and feasibility from the problem data alone.
fn assert_kkt(p: &QpProblem, s: &QpSolution, what: &str) {
    let grad = &p.p * &s.x + &p.q + p.a.transpose() * &s.z;
    let scale = 1.0 + p.q.norm() + (&p.p * &s.x).norm();
    assert!(
        grad.norm() < 1e-10 * scale,
        "{what}: stationarity {:e}",
        grad.norm()
    );
    let primal = &p.a * &s.x - &p.b;
    assert!(
        primal.norm() < 1e-10 * (1.0 + p.b.norm()),
        "{what}: primal {:e}",
        primal.norm()
    );
    assert!(
        s.s.norm() < 1e-10 * (1.0 + p.b.norm()),
        "{what}: slack {:e}",
        s.s.norm()
    );
}

fn cycle_problems() -> Vec<QpProblem> {
    let model = planner::model::builtin("drosophibot2").unwrap();
    let params = planner::gait::StepParams::table1("drosophibot2");
    let plan = planner::plan::plan(&model, &params).unwrap();
    let opts = DynamicsOptions::default();
    plan_inputs(&plan)
        .iter()
        .enumerate()
        .map(|(i, input)| slice_problem(&model, input, &opts, i).unwrap().qp)
        .collect()
}

#[test]
fn block_path_matches_null_space_path_on_every_slice_of_the_cycle() {
    let problems = cycle_problems();
    assert_eq!(problems.len(), 100);
    for (i, p) in problems.iter().enumerate() {
        // A foot's force only loads its own leg's joints, so P is block diagonal per stance foot.
        let block = qp::solve_block_diagonal(p)
            .unwrap_or_else(|| panic!("slice {i}: block path refused a block-diagonal P"));
        let general = qp::solve(p, Backend::NullSpace).unwrap();
        let auto = qp::solve(p, Backend::Auto).unwrap();
        assert_eq!(auto, block, "slice {i}: Auto did not take the block path");
        assert!(
            rel(&block.x, &general.x) < 1e-12,
            "slice {i}: x {:e}",
            rel(&block.x, &general.x)
        );
        assert!(
            rel(&block.z, &general.z) < 1e-12,
            "slice {i}: z {:e}",
            rel(&block.z, &general.z)
        );
        let f = |x: &DVector<f64>| 0.5 * x.dot(&(&p.p * x)) + p.q.dot(x);
        let (fb, fg) = (f(&block.x), f(&general.x));
        assert!(
            (fb - fg).abs() <= 1e-12 * fg.abs(),
            "slice {i}: objective {fb} vs {fg}"
        );
        assert_kkt(p, &block, &format!("slice {i}"));
    }
}

#[test]
fn hand_solved_problem() {
    // min x1^2 + x2^2 + 2 x3^2 subject to x1 + x2 + x3 = 1 and x1 - x2 = 0.2: P = diag(2, 2, 4)
    // (three 1x1 blocks). Stationarity 2 x1 + z1 + z2 = 0, 2 x2 + z1 - z2 = 0, 4 x3 + z1 = 0
    // with the constraints gives x = (0.5, 0.3, 0.2), z = (-0.8, -0.2).
    let p = QpProblem {
        p: DMatrix::from_diagonal(&DVector::from_vec(vec![2.0, 2.0, 4.0])),
        q: DVector::zeros(3),
        a: DMatrix::from_row_slice(2, 3, &[1.0, 1.0, 1.0, 1.0, -1.0, 0.0]),
        b: DVector::from_vec(vec![1.0, 0.2]),
        cones: vec![ConeBlock::Zero(2)],
    };
    let s = qp::solve_block_diagonal(&p).expect("diagonal P takes the block path");
    let x = DVector::from_vec(vec![0.5, 0.3, 0.2]);
    let z = DVector::from_vec(vec![-0.8, -0.2]);
    assert!(rel(&s.x, &x) < 1e-14, "x {}", s.x);
    assert!(rel(&s.z, &z) < 1e-14, "z {}", s.z);
    assert_eq!(qp::solve(&p, Backend::Auto).unwrap(), s);
}

#[test]
fn coupled_hessian_falls_back_to_the_null_space_path() {
    let mut p = cycle_problems().swap_remove(0);
    let n = p.q.len();
    assert!(n >= 6);
    // Couple the first and last foot by a small symmetric entry (P stays positive definite):
    // the one block would then span all n > 6 unknowns. (Coupling neighbours only merges two
    // 3x3 blocks into a 6x6 one, which the block path handles.)
    let c = 1e-3 * p.p[(0, 0)];
    p.p[(0, n - 1)] = c;
    p.p[(n - 1, 0)] = c;
    assert!(qp::solve_block_diagonal(&p).is_none());
    let auto = qp::solve(&p, Backend::Auto).unwrap();
    assert_eq!(auto, qp::solve(&p, Backend::NullSpace).unwrap());
    assert_kkt(&p, &auto, "coupled P");
}

#[test]
fn dependent_equality_rows_fall_back_to_the_null_space_path() {
    let mut p = cycle_problems().swap_remove(0);
    let (m, n) = p.a.shape();
    // Repeat the first equality row: A is then rank deficient and A P^-1 A' singular.
    let mut a = DMatrix::zeros(m + 1, n);
    a.rows_mut(0, m).copy_from(&p.a);
    a.row_mut(m).copy_from(&p.a.row(0));
    let mut b = DVector::zeros(m + 1);
    b.rows_mut(0, m).copy_from(&p.b);
    b[m] = p.b[0];
    (p.a, p.b, p.cones) = (a, b, vec![ConeBlock::Zero(m + 1)]);
    assert!(qp::solve_block_diagonal(&p).is_none());
    let auto = qp::solve(&p, Backend::Auto).unwrap();
    assert_eq!(auto, qp::solve(&p, Backend::NullSpace).unwrap());
    assert_kkt(&p, &auto, "dependent rows");
}

#[test]
fn indefinite_block_falls_back() {
    // P = diag(1, -1) with x2 fixed by the equality: unique optimum although P is indefinite,
    // so the block path must refuse it and the general path solve it: x = (-1, 2) for q = (1, 0).
    let p = QpProblem {
        p: DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, -1.0])),
        q: DVector::from_vec(vec![1.0, 0.0]),
        a: DMatrix::from_row_slice(1, 2, &[0.0, 1.0]),
        b: DVector::from_vec(vec![2.0]),
        cones: vec![ConeBlock::Zero(1)],
    };
    assert!(qp::solve_block_diagonal(&p).is_none());
    let s = qp::solve(&p, Backend::Auto).unwrap();
    assert!(
        rel(&s.x, &DVector::from_vec(vec![-1.0, 2.0])) < 1e-14,
        "x {}",
        s.x
    );
}

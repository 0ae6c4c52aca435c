//! The QP handed to Clarabel, restricted to the equality set (null-space parameterisation), so
//! that balance laws hold to rounding, not to the interior-point tolerance.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT, SupportedConeT::*,
};
use nalgebra::{DMatrix, DVector};

use super::{ConeBlock, QpError, QpProblem, QpSolution, ReducedEqualities};

/// Interior-point tolerances (Clarabel's default). The problems are scaled to unit size and the
/// equalities hold exactly, so this only bounds the optimality gap and the cone rows.
const TOLERANCE: f64 = 1e-8;

pub fn solve(
    problem: &QpProblem,
    eq: &ReducedEqualities,
    n_eq: usize,
    reduced_hessian: &DMatrix<f64>,
) -> Result<QpSolution, QpError> {
    // Clarabel sees the problem on the equality set, x = x_p + Z w: fewer unknowns, no equality
    // rows, and the equalities hold to rounding whatever the interior-point tolerance.
    let m_rest = problem.a.nrows() - n_eq;
    if eq.z.ncols() == 0 {
        return determined(problem, eq, n_eq);
    }
    let a_c = problem.a.rows(n_eq, m_rest);
    let b_c = problem.b.rows(n_eq, m_rest) - a_c * &eq.x_particular;
    let a_w = a_c * &eq.z;
    let q_w = eq.z.transpose() * (&problem.p * &eq.x_particular + &problem.q);

    let cones: Vec<SupportedConeT<f64>> = problem
        .cones
        .iter()
        .filter_map(|c| match *c {
            ConeBlock::Zero(_) => None,
            ConeBlock::Nonnegative(k) => Some(NonnegativeConeT(k)),
            ConeBlock::SecondOrder(k) => Some(SecondOrderConeT(k)),
        })
        .collect();
    let settings = DefaultSettings {
        verbose: false,
        tol_gap_abs: TOLERANCE,
        tol_gap_rel: TOLERANCE,
        tol_feas: TOLERANCE,
        // The problem is already scaled to unit size (see dynamics::problem); Ruiz equilibration
        // would only add setup time to every slice.
        equilibrate_enable: false,
        ..DefaultSettings::default()
    };
    let p_csc = csc(&reduced_hessian.upper_triangle());
    let a_csc = csc(&a_w);
    let mut solver = DefaultSolver::new(
        &p_csc,
        q_w.as_slice(),
        &a_csc,
        b_c.as_slice(),
        &cones,
        settings,
    )
    .map_err(|e| QpError::Setup {
        reason: e.to_string(),
    })?;
    solver.solve();
    let sol = &solver.solution;
    if sol.status != SolverStatus::Solved {
        return Err(QpError::Status {
            status: status_words(sol.status),
            iterations: sol.iterations,
        });
    }
    let x = &eq.x_particular + &eq.z * DVector::from_column_slice(&sol.x);
    let z_c = DVector::from_column_slice(&sol.z);
    // Equality multipliers from stationarity along the row space (its null-space part is
    // Clarabel's own optimality condition).
    let residual = &problem.p * &x + &problem.q + a_c.transpose() * &z_c;
    let z_hat = -(eq.v.transpose() * residual);
    let mut z = DVector::zeros(problem.a.nrows());
    z.rows_mut(0, n_eq).copy_from(&(&eq.multiplier_map * z_hat));
    z.rows_mut(n_eq, m_rest).copy_from(&z_c);
    let s = &problem.b - &problem.a * &x;
    Ok(QpSolution {
        x,
        s,
        z,
        iterations: sol.iterations,
    })
}

/// The equalities leave no freedom: x is x_p, feasible for the cones or not.
fn determined(
    problem: &QpProblem,
    eq: &ReducedEqualities,
    n_eq: usize,
) -> Result<QpSolution, QpError> {
    let x = eq.x_particular.clone();
    let s = &problem.b - &problem.a * &x;
    let mut row = n_eq;
    for c in &problem.cones {
        let k = c.rows();
        let v = s.rows(row, k);
        let inside = match c {
            ConeBlock::Zero(_) => true,
            ConeBlock::Nonnegative(_) => v.iter().all(|x| *x >= -TOLERANCE),
            ConeBlock::SecondOrder(_) => v[0] >= v.rows(1, k - 1).norm() - TOLERANCE,
        };
        if !inside {
            return Err(QpError::Status {
                status: status_words(SolverStatus::PrimalInfeasible),
                iterations: 0,
            });
        }
        row += k;
    }
    let z_hat = -(eq.v.transpose() * (&problem.p * &x + &problem.q));
    let mut z = DVector::zeros(problem.a.nrows());
    z.rows_mut(0, n_eq).copy_from(&(&eq.multiplier_map * z_hat));
    Ok(QpSolution {
        x,
        s,
        z,
        iterations: 0,
    })
}

fn csc(m: &DMatrix<f64>) -> CscMatrix<f64> {
    let (rows, cols) = m.shape();
    let mut colptr = Vec::with_capacity(cols + 1);
    let mut rowval = Vec::new();
    let mut nzval = Vec::new();
    colptr.push(0);
    for j in 0..cols {
        for i in 0..rows {
            let v = m[(i, j)];
            if v != 0.0 {
                rowval.push(i);
                nzval.push(v);
            }
        }
        colptr.push(rowval.len());
    }
    CscMatrix::new(rows, cols, colptr, rowval, nzval)
}

/// Clarabel's status in words.
fn status_words(status: SolverStatus) -> String {
    match status {
        SolverStatus::Unsolved => "not solved".into(),
        SolverStatus::Solved => "solved".into(),
        SolverStatus::PrimalInfeasible => {
            "infeasible (no load sharing meets the constraints)".into()
        }
        SolverStatus::DualInfeasible => "unbounded (dual infeasible)".into(),
        SolverStatus::AlmostSolved => "almost solved (inaccurate)".into(),
        SolverStatus::AlmostPrimalInfeasible => "almost infeasible".into(),
        SolverStatus::AlmostDualInfeasible => "almost unbounded".into(),
        SolverStatus::MaxIterations => "stopped at the iteration limit".into(),
        SolverStatus::MaxTime => "stopped at the time limit".into(),
        SolverStatus::NumericalError => "numerical error".into(),
        SolverStatus::InsufficientProgress => "insufficient progress".into(),
        SolverStatus::CallbackTerminated => "stopped by a callback".into(),
    }
}

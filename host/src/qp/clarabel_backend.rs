//! The QP handed to Clarabel: reduced equality rows first, then the cone rows as given; the
//! answer is polished onto the equality set so that balance laws hold to rounding, not to the
//! interior-point tolerance.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT, SupportedConeT::*,
};
use nalgebra::{DMatrix, DVector};

use super::{ConeBlock, QpError, QpProblem, QpSolution, ReducedEqualities};

/// Interior-point tolerances, tighter than Clarabel's defaults (1e-8) because the problems are
/// scaled to unit size and tiny.
const TOLERANCE: f64 = 1e-10;

pub fn solve(
    problem: &QpProblem,
    eq: &ReducedEqualities,
    n_eq: usize,
) -> Result<QpSolution, QpError> {
    let n = problem.q.len();
    let r = eq.v.ncols();
    let m_rest = problem.a.nrows() - n_eq;
    let mut a = DMatrix::zeros(r + m_rest, n);
    a.rows_mut(0, r).copy_from(&eq.v.transpose());
    a.rows_mut(r, m_rest)
        .copy_from(&problem.a.rows(n_eq, m_rest));
    let mut b = DVector::zeros(r + m_rest);
    b.rows_mut(0, r).copy_from(&eq.b_hat);
    b.rows_mut(r, m_rest)
        .copy_from(&problem.b.rows(n_eq, m_rest));

    let mut cones: Vec<SupportedConeT<f64>> = Vec::with_capacity(problem.cones.len() + 1);
    if r > 0 {
        cones.push(ZeroConeT(r));
    }
    for c in &problem.cones {
        match *c {
            ConeBlock::Zero(_) => {}
            ConeBlock::Nonnegative(k) => cones.push(NonnegativeConeT(k)),
            ConeBlock::SecondOrder(k) => cones.push(SecondOrderConeT(k)),
        }
    }

    let settings = DefaultSettings {
        verbose: false,
        tol_gap_abs: TOLERANCE,
        tol_gap_rel: TOLERANCE,
        tol_feas: TOLERANCE,
        tol_ktratio: 1e-8,
        ..DefaultSettings::default()
    };
    let p_csc = csc(&problem.p.upper_triangle());
    let a_csc = csc(&a);
    let mut solver = DefaultSolver::new(
        &p_csc,
        problem.q.as_slice(),
        &a_csc,
        b.as_slice(),
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
            status: format!("{:?}", sol.status),
            iterations: sol.iterations,
        });
    }
    let x = eq.project(&DVector::from_column_slice(&sol.x));
    let mut z = DVector::zeros(problem.a.nrows());
    let z_hat = DVector::from_column_slice(&sol.z[..r]);
    z.rows_mut(0, n_eq).copy_from(&(&eq.multiplier_map * z_hat));
    z.rows_mut(n_eq, m_rest)
        .copy_from(&DVector::from_column_slice(&sol.z[r..]));
    let s = &problem.b - &problem.a * &x;
    Ok(QpSolution {
        x,
        s,
        z,
        iterations: sol.iterations,
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

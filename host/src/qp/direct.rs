//! Direct solve of an equality-constrained QP by the null-space method: exact up to rounding,
//! and a few microseconds for the sizes of the dynamics problem.

use nalgebra::DMatrix;

use super::{QpProblem, QpSolution, ReducedEqualities};

/// Smallest over largest eigenvalue of a symmetric matrix (1 for an empty one, <= 0 if indefinite).
pub fn positive_definite_condition(h: &DMatrix<f64>) -> f64 {
    if h.is_empty() {
        return 1.0;
    }
    let eig = h.clone().symmetric_eigen();
    let max = eig.eigenvalues.max();
    let min = eig.eigenvalues.min();
    if max <= 0.0 { 0.0 } else { min / max }
}

/// Minimise over x = x_p + Z w. `reduced_hessian` is `Z' P Z`, already known positive definite.
pub fn solve(
    problem: &QpProblem,
    eq: &ReducedEqualities,
    reduced_hessian: &DMatrix<f64>,
) -> QpSolution {
    let xp = &eq.x_particular;
    let gradient_at_xp = &problem.p * xp + &problem.q;
    let rhs = -(eq.z.transpose() * &gradient_at_xp);
    let w = reduced_hessian
        .clone()
        .cholesky()
        .map(|c| c.solve(&rhs))
        .unwrap_or_else(|| {
            reduced_hessian
                .clone()
                .lu()
                .solve(&rhs)
                .unwrap_or(rhs.clone() * 0.0)
        });
    let x = xp + &eq.z * w;
    // Stationarity P x + q + A' z = 0 fixes the multipliers of the reduced rows exactly.
    let z_hat = -(eq.v.transpose() * (&problem.p * &x + &problem.q));
    let z = &eq.multiplier_map * z_hat;
    let s = &problem.b - &problem.a * &x;
    QpSolution {
        x,
        s,
        z,
        iterations: 0,
    }
}

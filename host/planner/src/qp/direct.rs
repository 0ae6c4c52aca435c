//! Direct solve of an equality-constrained QP by the null-space method: exact up to rounding,
//! and a few microseconds for the sizes of the dynamics problem.

use nalgebra::DMatrix;

use super::{QpProblem, QpSolution, ReducedEqualities};

/// Cheap condition estimate of a symmetric matrix from its Cholesky factor,
/// (min L_ii / max L_ii)^2: an estimate of the smallest-to-largest eigenvalue ratio (not a bound),
/// 0 when the factorisation fails (not positive definite), 1 for an empty matrix. A singular
/// positive semidefinite matrix gives pivots at rounding level, far below the tolerance.
pub fn positive_definite_condition(h: &DMatrix<f64>) -> f64 {
    if h.is_empty() {
        return 1.0;
    }
    match h.clone().cholesky() {
        None => 0.0,
        Some(c) => {
            let d = c.l_dirty().diagonal();
            let (lo, hi) = d.iter().fold((f64::INFINITY, 0.0f64), |(l, u), x| {
                (l.min(x.abs()), u.max(x.abs()))
            });
            if hi > 0.0 { (lo / hi).powi(2) } else { 0.0 }
        }
    }
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

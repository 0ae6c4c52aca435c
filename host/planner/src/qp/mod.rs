//! Small dense convex QPs with cone constraints: minimise 1/2 x'Px + q'x subject to Ax + s = b,
//! s in a product of cones (equalities first), solved either directly (equalities only) or with
//! Clarabel. Equality-only problems whose Hessian is block diagonal with small positive definite
//! blocks (the dynamics problem: one 3x3 block per stance foot) take a faster block/Schur path.
//!
//! The per-slice dynamics problem has at most 18 unknowns, so dense nalgebra matrices are the right
//! tool; Clarabel gets them as CSC. Equality rows may be linearly dependent (three feet in a line
//! cannot resist a moment about that line, which is fine when none is asked for): they are reduced
//! to an orthonormal basis of their row space first, and the multipliers are mapped back.

mod block;
mod clarabel_backend;
mod direct;
mod equality;

use nalgebra::{DMatrix, DVector};

pub use block::solve as solve_block_diagonal;
pub use equality::ReducedEqualities;

/// A block of constraint rows and the cone its slack lives in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConeBlock {
    /// `n` equality rows (slack zero).
    Zero(usize),
    /// `n` rows with nonnegative slack.
    Nonnegative(usize),
    /// One second-order cone of dimension `n`: s0 >= |s1..|.
    SecondOrder(usize),
}

impl ConeBlock {
    /// Number of rows of the block.
    pub fn rows(self) -> usize {
        match self {
            ConeBlock::Zero(n) | ConeBlock::Nonnegative(n) | ConeBlock::SecondOrder(n) => n,
        }
    }
}

/// A convex QP in Clarabel's standard form. `p` must be symmetric positive semidefinite.
#[derive(Debug, Clone, PartialEq)]
pub struct QpProblem {
    pub p: DMatrix<f64>,
    pub q: DVector<f64>,
    pub a: DMatrix<f64>,
    pub b: DVector<f64>,
    /// Row blocks of `a` in order; at most one `Zero` block, and it comes first.
    pub cones: Vec<ConeBlock>,
}

/// Which solver runs the QP.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Backend {
    /// Direct solve when there are only equalities (block/Schur when P is block diagonal with
    /// small positive definite blocks and the equality rows are independent, null space
    /// otherwise), Clarabel otherwise.
    #[default]
    Auto,
    /// As `Auto` but never the block/Schur path: the general null-space solve for equality-only
    /// problems (the reference the block path is tested against), Clarabel otherwise.
    NullSpace,
    /// Always Clarabel (also for equality-only problems).
    Clarabel,
}

/// Primal-dual solution: `x`, slacks `s` and multipliers `z` (one per row of `a`) with
/// `P x + q + A' z = 0`, `A x + s = b`, `s` in the cones, `z` in the dual cones, `s' z = 0`.
#[derive(Debug, Clone, PartialEq)]
pub struct QpSolution {
    pub x: DVector<f64>,
    pub s: DVector<f64>,
    pub z: DVector<f64>,
    /// Interior-point iterations (0 for the direct solve).
    pub iterations: u32,
}

/// Why a QP has no (unique) solution.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum QpError {
    #[error("the equality constraints are inconsistent (least-squares residual {residual:.3e})")]
    InconsistentEqualities { residual: f64 },
    #[error(
        "the optimum is not unique: the cost is flat along a direction the equalities leave free \
         (reduced Hessian condition {condition:.3e})"
    )]
    NotUnique { condition: f64 },
    #[error("Clarabel finished {status} after {iterations} iterations")]
    Status { status: String, iterations: u32 },
    #[error("Clarabel rejected the problem: {reason}")]
    Setup { reason: String },
    #[error("problem dimensions disagree: {what}")]
    Shape { what: String },
}

/// Smallest accepted ratio of the smallest to the largest eigenvalue of the reduced Hessian.
pub const UNIQUENESS_TOLERANCE: f64 = 1e-13;

/// Solve `problem`. The optimum must be unique: the Hessian restricted to the null space of the
/// equalities must be positive definite, which is checked before any solver runs.
pub fn solve(problem: &QpProblem, backend: Backend) -> Result<QpSolution, QpError> {
    check_shape(problem)?;
    let only_equalities = problem
        .cones
        .iter()
        .all(|c| matches!(c, ConeBlock::Zero(_)));
    // The block path proves uniqueness itself (P positive definite, equality rows independent)
    // and returns None for anything it cannot decide; the general path below then gives the
    // verdict, so errors are unchanged.
    if only_equalities
        && backend == Backend::Auto
        && let Some(solution) = block::solve(problem)
    {
        return Ok(solution);
    }
    let n_eq = match problem.cones.first() {
        Some(ConeBlock::Zero(n)) => *n,
        _ => 0,
    };
    let eq = ReducedEqualities::new(
        &problem.a.rows(0, n_eq).into_owned(),
        &problem.b.rows(0, n_eq).into_owned(),
    )?;
    let reduced_hessian = eq.null_space_hessian(&problem.p);
    let condition = direct::positive_definite_condition(&reduced_hessian);
    if condition < UNIQUENESS_TOLERANCE {
        return Err(QpError::NotUnique { condition });
    }
    if only_equalities && backend != Backend::Clarabel {
        Ok(direct::solve(problem, &eq, &reduced_hessian))
    } else {
        clarabel_backend::solve(problem, &eq, n_eq, &reduced_hessian)
    }
}

fn check_shape(p: &QpProblem) -> Result<(), QpError> {
    let n = p.q.len();
    let m: usize = p.cones.iter().map(|c| c.rows()).sum();
    let bad = |what: String| Err(QpError::Shape { what });
    if p.p.shape() != (n, n) {
        return bad(format!("P is {:?}, q has {n} entries", p.p.shape()));
    }
    if p.a.shape() != (m, n) || p.b.len() != m {
        return bad(format!(
            "A is {:?}, b has {}, cones have {m} rows",
            p.a.shape(),
            p.b.len()
        ));
    }
    if p.cones
        .iter()
        .skip(1)
        .any(|c| matches!(c, ConeBlock::Zero(_)))
    {
        return bad("a Zero cone block after the first block".into());
    }
    Ok(())
}

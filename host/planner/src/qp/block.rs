//! Fast path for equality-only QPs whose Hessian is block diagonal with small positive definite
//! blocks: Cholesky of each block and a Schur complement on the equality rows.
//!
//! In the per-slice dynamics problem P = B^T W B has one 3x3 block per stance foot (a foot's force
//! only loads the joints of its own leg), and there are at most 6 equality rows (thorax
//! equilibrium). Then the KKT system [P A'; A 0] [x; z] = [-q; b] is solved by eliminating x:
//! x = -P^-1 (q + A' z), (A P^-1 A') z = -(b + A P^-1 q). This replaces the equality reduction and
//! the null-space basis of the general path (docs/performance.md, "Profile of the step cycle").
//!
//! Anything this path cannot decide safely returns `None`, and `qp::solve` then runs the general
//! null-space path, which also produces the errors: P not block diagonal (checked exactly, entry by
//! entry), a block too large, not positive definite or badly conditioned, dependent equality rows
//! (the Schur complement is then singular).

use nalgebra::{DMatrix, DVector};

use super::{ConeBlock, QpProblem, QpSolution, UNIQUENESS_TOLERANCE, check_shape};

/// Largest diagonal block handled; bigger blocks gain nothing over the general path.
const MAX_BLOCK: usize = 6;
/// Smallest accepted (min/max Cholesky pivot)^2 over all blocks of P. Stricter than the general
/// path's uniqueness tolerance on the reduced Hessian Z'PZ (whose eigenvalues lie within those of
/// P), so that a problem near that limit goes to the general path and gets its verdict.
const BLOCK_CONDITION: f64 = 1e3 * UNIQUENESS_TOLERANCE;
/// Smallest accepted min/max Cholesky pivot of the Schur complement A P^-1 A': below it the
/// equality rows count as dependent (the same cut the equality reduction applies to A A').
const SCHUR_RANK_TOLERANCE: f64 = 1e-7;

/// Largest equality residual, relative to the size of `b` and of `A x`, that the fast path returns.
const EQUALITY_TOLERANCE: f64 = 1e-9;

/// Solve an equality-only `problem` (all rows of `a` are equalities) by the block/Schur method,
/// or `None` when it has other cones or inconsistent shapes, P is not block diagonal with small
/// well-conditioned positive definite blocks, the equality rows are (nearly) dependent, or the
/// result misses the equalities.
pub fn solve(problem: &QpProblem) -> Option<QpSolution> {
    check_shape(problem).ok()?;
    if !problem
        .cones
        .iter()
        .all(|c| matches!(c, ConeBlock::Zero(_)))
    {
        return None;
    }
    let n = problem.q.len();
    let m = problem.a.nrows();
    let blocks = diagonal_blocks(&problem.p)?;
    // Y = P^-1 [A' | q], block by block.
    let mut y = DMatrix::zeros(n, m + 1);
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for &(start, k) in &blocks {
        let chol = BlockCholesky::new(&problem.p, start, k)?;
        for i in 0..k {
            let d = chol.l[i * k + i];
            (lo, hi) = (lo.min(d), hi.max(d));
        }
        for c in 0..=m {
            let mut rhs = [0.0; MAX_BLOCK];
            for (i, r) in rhs.iter_mut().enumerate().take(k) {
                *r = if c < m {
                    problem.a[(c, start + i)]
                } else {
                    problem.q[start + i]
                };
            }
            chol.solve(&mut rhs[..k]);
            for (i, r) in rhs.iter().enumerate().take(k) {
                y[(start + i, c)] = *r;
            }
        }
    }
    // A NaN ratio (infinite entries) also falls back.
    let ratio = (lo / hi).powi(2);
    if n > 0 && (ratio.is_nan() || ratio < BLOCK_CONDITION) {
        return None;
    }
    let ay = &problem.a * &y; // m x (m + 1): [A P^-1 A' | A P^-1 q]
    let z = if m == 0 {
        DVector::zeros(0)
    } else {
        let schur = ay.columns(0, m).into_owned();
        let chol = schur.cholesky()?;
        let d = chol.l_dirty().diagonal();
        let (slo, shi) = d.iter().fold((f64::INFINITY, 0.0f64), |(l, u), x| {
            (l.min(x.abs()), u.max(x.abs()))
        });
        if slo.is_nan() || slo <= SCHUR_RANK_TOLERANCE * shi {
            return None;
        }
        chol.solve(&-(&problem.b + ay.column(m)))
    };
    let x = -(y.columns(0, m) * &z + y.column(m));
    let s = &problem.b - &problem.a * &x;
    // The rank test above is a pivot ratio: an inconsistent system (e.g. two feet that cannot
    // hold the body) can pass it and give an x that misses A x = b. Such a problem belongs to the
    // general path, which reports it; only a solution that meets the equalities is returned.
    let scale = problem.b.amax().max(problem.a.amax() * x.amax()).max(1.0);
    // A NaN residual fails this test too.
    if s.amax().partial_cmp(&(EQUALITY_TOLERANCE * scale)) != Some(std::cmp::Ordering::Less) {
        return None;
    }
    Some(QpSolution {
        x,
        s,
        z,
        iterations: 0,
    })
}

/// The exact block-diagonal structure of `p` as (start, size) pairs, or `None` when some nonzero
/// entry couples two blocks or a block is larger than `MAX_BLOCK`. A block closes at the first
/// index that no nonzero entry of the rows so far reaches past; an entry left of the current
/// block's start would couple it to a closed block.
fn diagonal_blocks(p: &DMatrix<f64>) -> Option<Vec<(usize, usize)>> {
    let n = p.nrows();
    let mut blocks = Vec::with_capacity(n.div_ceil(3));
    let mut start = 0;
    while start < n {
        let mut end = start + 1;
        let mut i = start;
        while i < end {
            for j in 0..n {
                if p[(i, j)] != 0.0 {
                    if j < start {
                        return None;
                    }
                    end = end.max(j + 1);
                }
            }
            i += 1;
            if end - start > MAX_BLOCK {
                return None;
            }
        }
        blocks.push((start, end - start));
        start = end;
    }
    Some(blocks)
}

/// Cholesky factor L (row-major, lower triangle) of one diagonal block of at most `MAX_BLOCK`
/// rows, on the stack: the blocks are tiny and heap allocations would dominate.
struct BlockCholesky {
    l: [f64; MAX_BLOCK * MAX_BLOCK],
    k: usize,
}

impl BlockCholesky {
    /// Factor `p[start..start+k, start..start+k]` from its lower triangle; `None` unless
    /// positive definite.
    fn new(p: &DMatrix<f64>, start: usize, k: usize) -> Option<Self> {
        let mut l = [0.0; MAX_BLOCK * MAX_BLOCK];
        for i in 0..k {
            for j in 0..=i {
                let mut sum = p[(start + i, start + j)];
                for t in 0..j {
                    sum -= l[i * k + t] * l[j * k + t];
                }
                if i == j {
                    // NaN is rejected too.
                    if sum.is_nan() || sum <= 0.0 {
                        return None;
                    }
                    l[i * k + i] = sum.sqrt();
                } else {
                    l[i * k + j] = sum / l[j * k + j];
                }
            }
        }
        Some(Self { l, k })
    }

    /// Overwrite `b` with the solution of L L' x = b.
    fn solve(&self, b: &mut [f64]) {
        let (l, k) = (&self.l, self.k);
        for i in 0..k {
            let mut v = b[i];
            for t in 0..i {
                v -= l[i * k + t] * b[t];
            }
            b[i] = v / l[i * k + i];
        }
        for i in (0..k).rev() {
            let mut v = b[i];
            for t in i + 1..k {
                v -= l[t * k + i] * b[t];
            }
            b[i] = v / l[i * k + i];
        }
    }
}

//! Equality constraints reduced to an orthonormal basis of their row space, with a particular
//! solution and a null-space basis, so that dependent rows are harmless and uniqueness can be checked.

use nalgebra::{DMatrix, DVector};

use super::QpError;

/// Relative singular-value cut below which an equality row direction counts as dependent.
const RANK_TOLERANCE: f64 = 1e-7;
/// Relative least-squares residual above which equalities count as inconsistent.
const CONSISTENCY_TOLERANCE: f64 = 1e-9;

/// `A x = b` rewritten as `V' x = b_hat` with orthonormal rows `V'` (r of them), plus the map back.
#[derive(Debug, Clone, PartialEq)]
pub struct ReducedEqualities {
    /// n x r, orthonormal columns spanning the row space of A.
    pub v: DMatrix<f64>,
    /// Right-hand side of the reduced rows.
    pub b_hat: DVector<f64>,
    /// m x r map from reduced multipliers to multipliers of the original rows: `z = map * z_hat`.
    pub multiplier_map: DMatrix<f64>,
    /// n x (n - r), orthonormal basis of the null space of A.
    pub z: DMatrix<f64>,
    /// The minimum-norm solution of A x = b.
    pub x_particular: DVector<f64>,
}

impl ReducedEqualities {
    /// Reduce `a x = b` (m rows, n unknowns).
    pub fn new(a: &DMatrix<f64>, b: &DVector<f64>) -> Result<Self, QpError> {
        let n = a.ncols();
        let m = a.nrows();
        let (v, b_hat, multiplier_map) = if m == 0 || n == 0 {
            (
                DMatrix::zeros(n, 0),
                DVector::zeros(0),
                DMatrix::zeros(m, 0),
            )
        } else if let Some(fast) = full_rank(a, b) {
            fast
        } else {
            // Row space from the eigen decomposition of the small Gram matrix A A' = U S^2 U'
            // (m <= 6 here): V = A' U / S. Much cheaper than an SVD of A, and accurate enough
            // because the scaled equality rows are well conditioned or exactly dependent.
            let eig = (a * a.transpose()).symmetric_eigen();
            let sigma: Vec<f64> = eig.eigenvalues.iter().map(|l| l.max(0.0).sqrt()).collect();
            let s_max = sigma.iter().copied().fold(0.0, f64::max);
            let keep: Vec<usize> = (0..m)
                .filter(|&i| sigma[i] > RANK_TOLERANCE * s_max && sigma[i] > 0.0)
                .collect();
            let r = keep.len();
            let mut v = DMatrix::zeros(n, r);
            let mut b_hat = DVector::zeros(r);
            let mut map = DMatrix::zeros(m, r);
            for (k, &i) in keep.iter().enumerate() {
                let u = eig.eigenvectors.column(i);
                v.set_column(k, &(a.transpose() * u / sigma[i]));
                b_hat[k] = u.dot(b) / sigma[i];
                map.set_column(k, &(u / sigma[i]));
            }
            (v, b_hat, map)
        };
        let x_particular = &v * &b_hat;
        let residual = (a * &x_particular - b).norm();
        if residual > CONSISTENCY_TOLERANCE * b.norm().max(1.0) {
            return Err(QpError::InconsistentEqualities { residual });
        }
        let z = orthogonal_complement(&v);
        Ok(Self {
            v,
            b_hat,
            multiplier_map,
            z,
            x_particular,
        })
    }

    /// `Z' P Z`: the Hessian on the directions the equalities leave free.
    pub fn null_space_hessian(&self, p: &DMatrix<f64>) -> DMatrix<f64> {
        self.z.transpose() * p * &self.z
    }

    /// Move `x` onto the equality set along the row space (the smallest correction).
    pub fn project(&self, x: &DVector<f64>) -> DVector<f64> {
        let r = self.v.transpose() * x - &self.b_hat;
        x - &self.v * r
    }
}

/// The common case, rows independent: A A' = L L' (Cholesky), V = A' L^-T has orthonormal
/// columns, b_hat = L^-1 b, multipliers map back through L^-T. `None` when the rows are
/// (nearly) dependent, judged by the Cholesky pivots.
fn full_rank(
    a: &DMatrix<f64>,
    b: &DVector<f64>,
) -> Option<(DMatrix<f64>, DVector<f64>, DMatrix<f64>)> {
    let m = a.nrows();
    if m > a.ncols() {
        return None;
    }
    let chol = (a * a.transpose()).cholesky()?;
    let l = chol.l();
    let d = l.diagonal();
    let (lo, hi) = d.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), x| {
        (lo.min(x.abs()), hi.max(x.abs()))
    });
    if lo.is_nan() || lo <= RANK_TOLERANCE * hi {
        return None;
    }
    let l_inv = l.try_inverse()?;
    let map = l_inv.transpose();
    let v = a.transpose() * &map;
    let b_hat = &l_inv * b;
    Some((v, b_hat, map))
}

/// An orthonormal basis of the complement of the orthonormal columns of `v`: the last n - r
/// columns of the full Q of a Householder QR of `v`.
fn orthogonal_complement(v: &DMatrix<f64>) -> DMatrix<f64> {
    let (n, r) = v.shape();
    let mut work = v.clone();
    let mut reflectors: Vec<DVector<f64>> = Vec::with_capacity(r);
    for k in 0..r {
        let mut h = DVector::zeros(n);
        let x = work.view((k, k), (n - k, 1));
        let norm = x.norm();
        let alpha = if x[0] >= 0.0 { -norm } else { norm };
        h.rows_mut(k, n - k).copy_from(&x);
        h[k] -= alpha;
        let hn = h.norm();
        if hn > 0.0 {
            h /= hn;
        }
        // Apply I - 2 h h' to the remaining columns.
        for c in k..r {
            let d = 2.0 * h.dot(&work.column(c));
            work.column_mut(c).axpy(-d, &h, 1.0);
        }
        reflectors.push(h);
    }
    let mut z = DMatrix::zeros(n, n - r);
    for (c, j) in (r..n).enumerate() {
        let mut e = DVector::zeros(n);
        e[j] = 1.0;
        for h in reflectors.iter().rev() {
            let d = 2.0 * h.dot(&e);
            e.axpy(-d, h, 1.0);
        }
        z.set_column(c, &e);
    }
    z
}

//! Equality constraints reduced to an orthonormal basis of their row space, with a particular
//! solution and a null-space basis, so that dependent rows are harmless and uniqueness can be checked.

use nalgebra::{DMatrix, DVector};

use super::QpError;

/// Relative singular-value cut below which an equality row direction counts as dependent.
const RANK_TOLERANCE: f64 = 1e-10;
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
        } else {
            let svd = a.clone().svd(true, true);
            let (u, vt) = (svd.u.expect("requested"), svd.v_t.expect("requested"));
            let s_max = svd.singular_values.max();
            let keep: Vec<usize> = (0..svd.singular_values.len())
                .filter(|&i| svd.singular_values[i] > RANK_TOLERANCE * s_max.max(f64::MIN_POSITIVE))
                .collect();
            let r = keep.len();
            let mut v = DMatrix::zeros(n, r);
            let mut b_hat = DVector::zeros(r);
            let mut map = DMatrix::zeros(m, r);
            for (k, &i) in keep.iter().enumerate() {
                let sigma = svd.singular_values[i];
                v.set_column(k, &vt.row(i).transpose());
                b_hat[k] = u.column(i).dot(b) / sigma;
                map.set_column(k, &(u.column(i) / sigma));
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

/// An orthonormal basis of the complement of the orthonormal columns of `v` (modified Gram-Schmidt
/// over the unit vectors, twice for stability).
fn orthogonal_complement(v: &DMatrix<f64>) -> DMatrix<f64> {
    let n = v.nrows();
    let mut basis: Vec<DVector<f64>> = v.column_iter().map(|c| c.into_owned()).collect();
    let first_new = basis.len();
    for k in 0..n {
        if basis.len() == n {
            break;
        }
        let mut e = DVector::zeros(n);
        e[k] = 1.0;
        for _ in 0..2 {
            for b in &basis {
                let d = b.dot(&e);
                e.axpy(-d, b, 1.0);
            }
        }
        let norm = e.norm();
        if norm > 0.3 {
            basis.push(e / norm);
        }
    }
    let cols = &basis[first_new..];
    let mut z = DMatrix::zeros(n, cols.len());
    for (k, c) in cols.iter().enumerate() {
        z.set_column(k, c);
    }
    z
}

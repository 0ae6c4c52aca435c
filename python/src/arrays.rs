//! The host's per-slice rows (`Vec<Vec<T>>`: [slice][joint] or [slice][leg]) as 2-D NumPy arrays:
//! the one converter behind `Plan` and `PlanDir`.

use numpy::ndarray::Array2;
use numpy::{Element, PyArray2, ToPyArray};
use pyo3::prelude::*;

/// `v[i][j]` as an array [i, j]; the width is the first row's (rows are equally long).
pub fn rows<'py, T: Element + Copy>(py: Python<'py>, v: &[Vec<T>]) -> Bound<'py, PyArray2<T>> {
    let cols = v.first().map_or(0, Vec::len);
    Array2::from_shape_fn((v.len(), cols), |(i, j)| v[i][j]).to_pyarray(py)
}

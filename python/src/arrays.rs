//! Host values as NumPy arrays: the per-slice rows (`Vec<Vec<T>>`: [slice][joint] or
//! [slice][leg]) as 2-D arrays, the one converter behind `Plan` and `PlanDir`; and a new array
//! written in place ([`written`]), for the arrays made every step.

use numpy::ndarray::{Array2, Dimension, IntoDimension};
use numpy::{Element, PyArray, PyArray2, PyArrayMethods, ToPyArray};
use pyo3::prelude::*;

/// A new array of `dims`, zeroed by NumPy, then written in place by `fill` (its elements in
/// C order): no vector in between, for the arrays a step makes (an environment's observation,
/// masks and body).
pub fn written<'py, T: Element, D: Dimension>(
    py: Python<'py>,
    dims: impl IntoDimension<Dim = D>,
    fill: impl FnOnce(&mut [T]),
) -> Bound<'py, PyArray<T, D>> {
    let a = PyArray::<T, D>::zeros(py, dims, false);
    // SAFETY: the array was just made here and nothing else holds it.
    fill(unsafe { a.as_slice_mut() }.expect("a new C-order array is contiguous"));
    a
}

/// `v[i][j]` as an array [i, j]; the width is the first row's (rows are equally long).
pub fn rows<'py, T: Element + Copy>(py: Python<'py>, v: &[Vec<T>]) -> Bound<'py, PyArray2<T>> {
    let cols = v.first().map_or(0, Vec::len);
    Array2::from_shape_fn((v.len(), cols), |(i, j)| v[i][j]).to_pyarray(py)
}

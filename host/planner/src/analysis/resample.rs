//! Periodic resampling, so that two plans with different slice counts can be compared slice by
//! slice.

/// Resample one period of a periodic trace (samples at t = i / len of the cycle) to `n` samples
/// by linear interpolation, so that two plans with different slice counts can be compared.
pub fn resample_periodic(v: &[f64], n: usize) -> Vec<f64> {
    if v.is_empty() || v.len() == n {
        return v.to_vec();
    }
    let m = v.len();
    (0..n)
        .map(|i| {
            let t = i as f64 * m as f64 / n as f64;
            let k = t.floor() as usize % m;
            let f = t - t.floor();
            v[k] * (1.0 - f) + v[(k + 1) % m] * f
        })
        .collect()
}

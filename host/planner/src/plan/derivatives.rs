//! Periodic central differences (equations 1 and 2 of the paper): slice 0's predecessor is the last
//! slice and the last slice's successor is slice 0.

/// `(x[t+1] - x[t-1]) / (2 dt)` per component, indices wrapping around the cycle.
pub fn periodic_central_difference(x: &[Vec<f64>], dt: f64) -> Vec<Vec<f64>> {
    let n = x.len();
    (0..n)
        .map(|t| {
            let (next, prev) = (&x[(t + 1) % n], &x[(t + n - 1) % n]);
            next.iter()
                .zip(prev)
                .map(|(a, b)| (a - b) / (2.0 * dt))
                .collect()
        })
        .collect()
}

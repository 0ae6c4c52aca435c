//! Simple linear regression and periodic resampling.

/// Coefficient of determination of the least-squares line y = a + b x (the squared Pearson
/// correlation). `None` if the lengths differ, fewer than 3 points, or either trace is constant.
pub fn r_squared(x: &[f64], y: &[f64]) -> Option<f64> {
    if x.len() != y.len() || x.len() < 3 {
        return None;
    }
    let n = x.len() as f64;
    let mx = x.iter().sum::<f64>() / n;
    let my = y.iter().sum::<f64>() / n;
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in x.iter().zip(y) {
        sxy += (a - mx) * (b - my);
        sxx += (a - mx) * (a - mx);
        syy += (b - my) * (b - my);
    }
    // A trace that does not move has no regression (e.g. a DoF idle during a step).
    let tiny = f64::EPSILON * n;
    if sxx <= tiny * (mx * mx).max(f64::MIN_POSITIVE)
        || syy <= tiny * (my * my).max(f64::MIN_POSITIVE)
    {
        return None;
    }
    Some((sxy * sxy) / (sxx * syy))
}

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

//! Speed sweep: how the peak torque scales with the step period tells a quasi-static regime
//! (torque independent of period: gravity dominates) from an inertial one (torque ~ 1/T^2).

/// Peak actuated torque of one plan of the sweep.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SweepPoint {
    /// Step period, s.
    pub period: f64,
    /// Largest |torque| over joints and slices, N m.
    pub peak_torque: f64,
    /// Largest |torque| of the same plan with gravity removed (inertial part only), N m.
    pub peak_inertial_torque: f64,
}

/// Verdict of a sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepRegime {
    /// Log-log slope of the inertial peak against the period (-2 for pure inertia).
    pub inertial_exponent: f64,
    /// Inertial share of the peak torque at each period: below ~0.1 the step is quasi-static.
    pub inertial_share: Vec<f64>,
}

/// Fit the log-log slope of the inertial torque against the period and each point's inertial share.
/// `None` with fewer than two points or non-positive values.
pub fn classify_sweep(points: &[SweepPoint]) -> Option<SweepRegime> {
    if points.len() < 2
        || points
            .iter()
            .any(|p| p.period <= 0.0 || p.peak_inertial_torque <= 0.0)
    {
        return None;
    }
    let xs: Vec<f64> = points.iter().map(|p| p.period.ln()).collect();
    let ys: Vec<f64> = points.iter().map(|p| p.peak_inertial_torque.ln()).collect();
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    if sxx == 0.0 {
        return None;
    }
    let inertial_share = points
        .iter()
        .map(|p| {
            if p.peak_torque > 0.0 {
                p.peak_inertial_torque / p.peak_torque
            } else {
                0.0
            }
        })
        .collect();
    Some(SweepRegime {
        inertial_exponent: sxy / sxx,
        inertial_share,
    })
}

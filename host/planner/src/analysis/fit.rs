//! Fit statistics: the one owner of R^2 and RMS figures in the workspace (the paper's comparison
//! tables, the paper-robot tables, the demo's walk fits).
//!
//! Two different R^2 are in use, under two names:
//! - [`regression_r2`]: the squared Pearson correlation of two traces, i.e. the R^2 of the
//!   least-squares line y = a + b x. Symmetric, in 0..=1, blind to an offset or a scale between
//!   the traces: the paper's tables S2 to S8 compare a robot's and a fly's traces this way.
//! - [`prediction_r2`]: the coefficient of determination of a model that predicts measurements
//!   without being fitted to them, 1 - SS_res / SS_tot (SS_tot about the measurements' mean):
//!   1 when the model predicts every sample, 0 when it predicts no better than the measured mean,
//!   negative when worse. The demo's plan-versus-simulation fits and the paper-robot tables.
//!
//! Both need at least [`MIN_SAMPLES`] samples and measurements that vary (else `None`).

/// Fewest samples an R^2 is computed from: a line through two points fits them exactly, so a
/// regression needs three, and a prediction is held to the same count.
pub const MIN_SAMPLES: usize = 3;

/// Whether a sum of squares about the mean `mean` of `n` samples is zero up to rounding (a trace
/// that does not move, e.g. a DoF idle during a step, has no R^2).
fn flat(ss: f64, mean: f64, n: usize) -> bool {
    ss <= f64::EPSILON * n as f64 * (mean * mean).max(f64::MIN_POSITIVE)
}

fn mean(xs: impl Iterator<Item = f64>) -> f64 {
    let (n, sum) = xs.fold((0usize, 0.0), |(n, s), x| (n + 1, s + x));
    sum / n.max(1) as f64
}

/// The least-squares line `y = slope x + intercept` through the first `n` pairs of `x` and `y`
/// (`n` the shorter length), with the sums its standard errors need.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Line {
    pub slope: f64,
    pub intercept: f64,
    /// The mean of `x`.
    pub mean_x: f64,
    /// The sum of squares of `x` about its mean.
    pub sxx: f64,
}

/// Fits [`Line`]; `None` with fewer than two pairs or an `x` that does not vary (`sxx` at most
/// 1e-12).
pub fn line(x: &[f64], y: &[f64]) -> Option<Line> {
    let n = x.len().min(y.len());
    if n < 2 {
        return None;
    }
    let (x, y) = (&x[..n], &y[..n]);
    let mean_x = x.iter().sum::<f64>() / n as f64;
    let mean_y = y.iter().sum::<f64>() / n as f64;
    let sxx: f64 = x.iter().map(|v| (v - mean_x).powi(2)).sum();
    if sxx <= 1e-12 {
        return None;
    }
    let sxy: f64 = x
        .iter()
        .zip(y)
        .map(|(a, b)| (a - mean_x) * (b - mean_y))
        .sum();
    let slope = sxy / sxx;
    Some(Line {
        slope,
        intercept: mean_y - slope * mean_x,
        mean_x,
        sxx,
    })
}

/// Squared Pearson correlation of `x` and `y` (the R^2 of the least-squares line y = a + b x).
/// `None` if the lengths differ, there are fewer than [`MIN_SAMPLES`] points, or either trace is
/// constant.
pub fn regression_r2(x: &[f64], y: &[f64]) -> Option<f64> {
    if x.len() != y.len() || x.len() < MIN_SAMPLES {
        return None;
    }
    let n = x.len();
    let mx = mean(x.iter().copied());
    let my = mean(y.iter().copied());
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in x.iter().zip(y) {
        sxy += (a - mx) * (b - my);
        sxx += (a - mx) * (a - mx);
        syy += (b - my) * (b - my);
    }
    if flat(sxx, mx, n) || flat(syy, my, n) {
        return None;
    }
    Some((sxy * sxy) / (sxx * syy))
}

/// 1 - SS_res / SS_tot of a model predicting measurements: `pairs` are (measured, predicted).
/// `None` with fewer than [`MIN_SAMPLES`] pairs or measurements that do not vary.
pub fn prediction_r2(pairs: &[(f64, f64)]) -> Option<f64> {
    let n = pairs.len();
    if n < MIN_SAMPLES {
        return None;
    }
    let m = mean(pairs.iter().map(|p| p.0));
    let ss_tot: f64 = pairs.iter().map(|p| (p.0 - m).powi(2)).sum();
    let ss_res: f64 = pairs.iter().map(|p| (p.0 - p.1).powi(2)).sum();
    (!flat(ss_tot, m, n)).then(|| 1.0 - ss_res / ss_tot)
}

/// Root mean square of `xs` (`None` when there are none).
pub fn rms(xs: impl IntoIterator<Item = f64>) -> Option<f64> {
    let (n, sq) = xs
        .into_iter()
        .fold((0usize, 0.0), |(n, sq), x| (n + 1, sq + x * x));
    (n > 0).then(|| (sq / n as f64).sqrt())
}

/// Root mean square of measured - predicted over `pairs` (measured, predicted).
pub fn rms_difference(pairs: &[(f64, f64)]) -> Option<f64> {
    rms(pairs.iter().map(|(m, p)| m - p))
}

/// Mean and population standard deviation of some samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeanSd {
    pub mean: f64,
    pub sd: f64,
    pub n: usize,
}

/// Running sums for [`MeanSd`], one sample at a time (per slice of a step, per joint).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MeanSdSums {
    n: usize,
    sum: f64,
    sq: f64,
}

impl MeanSdSums {
    pub fn add(&mut self, x: f64) {
        self.n += 1;
        self.sum += x;
        self.sq += x * x;
    }

    /// The statistics so far (`None` before the first sample).
    pub fn finish(&self) -> Option<MeanSd> {
        (self.n > 0).then(|| {
            let mean = self.sum / self.n as f64;
            MeanSd {
                mean,
                sd: (self.sq / self.n as f64 - mean * mean).max(0.0).sqrt(),
                n: self.n,
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_through_exact_points_is_found_and_a_flat_x_has_none() {
        // y = 2 x + 1 at x = 0, 1, 2 (y longer than x: only the pairs count); by hand mean x 1,
        // sxx 2.
        let l = line(&[0.0, 1.0, 2.0], &[1.0, 3.0, 5.0, 99.0]).unwrap();
        assert_eq!(
            (l.slope, l.intercept, l.mean_x, l.sxx),
            (2.0, 1.0, 1.0, 2.0)
        );
        assert_eq!(line(&[1.0, 1.0], &[0.0, 5.0]), None);
        assert_eq!(line(&[1.0], &[0.0]), None);
    }

    #[test]
    fn regression_r2_is_the_squared_correlation_of_a_hand_worked_case() {
        // x 1 2 3, y 1 3 2: means 2 and 2; sxy = (-1)(-1) + 0 + (1)(0) = 1, sxx = 2, syy = 2:
        // r^2 = 1 / 4.
        assert!((regression_r2(&[1.0, 2.0, 3.0], &[1.0, 3.0, 2.0]).unwrap() - 0.25).abs() < 1e-15);
        // A scaled and offset copy correlates perfectly.
        assert!(
            (regression_r2(&[1.0, 2.0, 4.0], &[12.0, 14.0, 18.0]).unwrap() - 1.0).abs() < 1e-15
        );
        assert_eq!(regression_r2(&[1.0, 2.0], &[1.0, 3.0]), None);
        assert_eq!(regression_r2(&[1.0, 2.0, 3.0], &[5.0; 3]), None);
    }

    #[test]
    fn prediction_r2_is_one_for_a_perfect_model_zero_for_the_mean_and_negative_when_worse() {
        assert_eq!(
            prediction_r2(&[(1.0, 1.0), (2.0, 2.0), (3.0, 3.0)]),
            Some(1.0)
        );
        // The mean (2) predicts with SS_res = SS_tot = 2: R^2 = 0.
        assert!(
            prediction_r2(&[(1.0, 2.0), (2.0, 2.0), (3.0, 2.0)])
                .unwrap()
                .abs()
                < 1e-12
        );
        // Reversed: SS_res = 4 + 0 + 4 = 8, SS_tot = 2: R^2 = -3 (the regression's r^2 is 1).
        let reversed = [(1.0, 3.0), (2.0, 2.0), (3.0, 1.0)];
        assert!((prediction_r2(&reversed).unwrap() + 3.0).abs() < 1e-12);
        assert!((regression_r2(&[1.0, 2.0, 3.0], &[3.0, 2.0, 1.0]).unwrap() - 1.0).abs() < 1e-15);
        // A scale the regression forgives: predicted 2x measured. SS_res = 1 + 4 + 9 = 14,
        // SS_tot = 2: R^2 = -6.
        let scaled = [(1.0, 2.0), (2.0, 4.0), (3.0, 6.0)];
        assert!((prediction_r2(&scaled).unwrap() + 6.0).abs() < 1e-12);
        assert_eq!(prediction_r2(&[(1.0, 0.0), (1.0, 2.0), (1.0, 1.0)]), None);
        assert_eq!(prediction_r2(&[(1.0, 1.0), (2.0, 2.0)]), None);
        assert_eq!(prediction_r2(&[]), None);
    }

    #[test]
    fn rms_and_mean_sd_match_hand_calculations() {
        assert_eq!(rms([3.0, 4.0]), Some(12.5f64.sqrt()));
        assert_eq!(rms([]), None);
        // The mean (2) predicting 1 2 3: RMS sqrt(2 / 3).
        let d = rms_difference(&[(1.0, 2.0), (2.0, 2.0), (3.0, 2.0)]).unwrap();
        assert!((d - (2.0f64 / 3.0).sqrt()).abs() < 1e-15);
        let mut s = MeanSdSums::default();
        assert_eq!(s.finish(), None);
        for x in [2.0, 4.0] {
            s.add(x);
        }
        assert_eq!(
            s.finish(),
            Some(MeanSd {
                mean: 3.0,
                sd: 1.0,
                n: 2
            })
        );
    }
}

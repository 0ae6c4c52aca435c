//! The Present Load reading of one joint, fitted from the load alone once the motion is fitted:
//! the recorded reading (N m through the register's nominal conversion, joint direction)
//! against the replayed actuator torque is a line, `gain x torque + offset` (ordinary least
//! squares, standard errors from the residual); the resolution is the greatest common divisor of
//! the recorded counts' changes; the noise is what the residual's spread leaves beyond the
//! resolution's rounding (uniform, step^2 / 12).

/// A joint's fitted reading.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoadFit {
    pub gain: f64,
    pub gain_sd: f64,
    /// Offset in the joint's direction, N m (the model's `load_offset_nm` is in the servo's).
    pub offset_nm: f64,
    pub offset_sd: f64,
    pub resolution_counts: u16,
    pub noise_nm: f64,
}

/// Fits `recorded` (N m) against `torque` (N m); `raw` the recorded counts and `nm_per_count`
/// the register's unit. `None` when the torque does not vary (nothing to fit a gain to).
pub fn fit(recorded: &[f64], torque: &[f64], raw: &[i16], nm_per_count: f64) -> Option<LoadFit> {
    let n = recorded.len().min(torque.len());
    if n < 3 {
        return None;
    }
    let l = planner::analysis::fit::line(&torque[..n], &recorded[..n])?;
    let (gain, offset, mx, sxx) = (l.slope, l.intercept, l.mean_x, l.sxx);
    let ss: f64 = torque[..n]
        .iter()
        .zip(&recorded[..n])
        .map(|(x, y)| (y - gain * x - offset).powi(2))
        .sum();
    let var = ss / (n - 2) as f64;
    let gain_sd = (var / sxx).sqrt();
    let offset_sd = (var * (1.0 / n as f64 + mx * mx / sxx)).sqrt();
    let resolution = raw
        .windows(2)
        .map(|w| (i32::from(w[1]) - i32::from(w[0])).unsigned_abs())
        .filter(|&d| d > 0)
        .fold(0, gcd)
        .max(1);
    let step = f64::from(resolution) * nm_per_count;
    let noise_nm = (var - step * step / 12.0).max(0.0).sqrt();
    Some(LoadFit {
        gain,
        gain_sd,
        offset_nm: offset,
        offset_sd,
        resolution_counts: resolution.min(u32::from(u16::MAX)) as u16,
        noise_nm,
    })
}

fn gcd(a: u32, b: u32) -> u32 {
    if b == 0 { a } else { gcd(b, a % b) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_with_steps_is_recovered() {
        // Readings 0.8 x torque + 0.05, in steps of 2 counts of 0.01 N m: the gain and offset
        // come back within the rounding, the resolution exactly, and no noise is left.
        let torque: Vec<f64> = (0..400).map(|i| (f64::from(i) * 0.05).sin()).collect();
        let raw: Vec<i16> = torque
            .iter()
            .map(|t| ((0.8 * t + 0.05) / 0.02).round() as i16 * 2)
            .collect();
        let rec: Vec<f64> = raw.iter().map(|&r| f64::from(r) * 0.01).collect();
        let f = fit(&rec, &torque, &raw, 0.01).unwrap();
        assert!((f.gain - 0.8).abs() < 0.005, "{f:?}");
        assert!((f.offset_nm - 0.05).abs() < 0.003, "{f:?}");
        assert_eq!(f.resolution_counts, 2);
        assert!(f.noise_nm < 0.002, "{f:?}");
    }
}

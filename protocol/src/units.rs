//! Fixed-point units of the device side and checked conversions from SI.
//!
//! The host plans in f64 SI units; the board stores and computes in small integers. Conversions
//! round to nearest and refuse values that do not fit instead of wrapping.

/// Angle units per radian: angles are `i16` in 1e-4 rad (+-3.2767 rad).
pub const ANGLE_PER_RAD: f64 = 10_000.0;
/// Torque units per newton metre: torques are `i16` in mN m (+-32.767 N m).
pub const TORQUE_PER_NM: f64 = 1_000.0;
/// Velocity units per rad/s: velocities are `i16` in 1e-3 rad/s.
pub const VELOCITY_PER_RAD_S: f64 = 1_000.0;
/// Stiffness units per N m/rad: stiffness is `u32` in mN m/rad.
pub const STIFFNESS_PER_NM_RAD: f64 = 1_000.0;
/// Duty factor units: `u16` in 1e-4 of the step period.
pub const DUTY_PER_UNIT: f64 = 10_000.0;
/// Period scale units: `u16` in 1e-3 (1000 plays the step at its planned period).
pub const PERIOD_SCALE_ONE: u16 = 1_000;

/// Converts `value * scale` to the integer range `[min, max]`, rounding to nearest.
///
/// `None` when the value is not finite or the rounded result is outside the range.
#[cfg(feature = "std")]
pub fn to_fixed(value: f64, scale: f64, min: i64, max: i64) -> Option<i64> {
    let scaled = (value * scale).round();
    if !scaled.is_finite() || scaled < min as f64 || scaled > max as f64 {
        return None;
    }
    Some(scaled as i64)
}

/// Angle in radians from fixed-point units.
pub fn angle_to_rad(angle: i16) -> f64 {
    f64::from(angle) / ANGLE_PER_RAD
}

/// Torque in newton metres from fixed-point units.
pub fn torque_to_nm(torque: i16) -> f64 {
    f64::from(torque) / TORQUE_PER_NM
}

/// Integer division rounding half away from zero.
pub fn div_round(num: i64, den: i64) -> i64 {
    if (num < 0) == (den < 0) {
        (num + den / 2) / den
    } else {
        (num - den / 2) / den
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn division_rounds_half_away_from_zero() {
        assert_eq!(div_round(5, 2), 3);
        assert_eq!(div_round(-5, 2), -3);
        assert_eq!(div_round(4, 3), 1);
        assert_eq!(div_round(-4, 3), -1);
        assert_eq!(div_round(5, -2), -3);
    }
}

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
/// Servo ticks per revolution of a Dynamixel MX (2.0).
pub const TICKS_PER_REV: i32 = 4096;

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

/// Angle units (1e-4 rad) to servo ticks, exact integer arithmetic rounded to nearest.
///
/// ticks = angle * 4096 / (2 pi * 1e4); 2 pi * 1e4 is taken as 62_831.853_07 (to 1e-9 relative)
/// by scaling numerator and denominator by 1e5.
pub fn angle_units_to_ticks(angle: i32) -> i32 {
    const TWO_PI_E9: i64 = 6_283_185_307; // 2 pi * 1e4 * 1e5
    let num = i64::from(angle) * i64::from(TICKS_PER_REV) * 100_000;
    div_round(num, TWO_PI_E9) as i32
}

/// Servo ticks to angle units (1e-4 rad), rounded to nearest.
pub fn ticks_to_angle_units(ticks: i32) -> i32 {
    const TWO_PI_E9: i64 = 6_283_185_307;
    let num = i64::from(ticks) * TWO_PI_E9;
    div_round(num, i64::from(TICKS_PER_REV) * 100_000) as i32
}

/// Integer division rounding half away from zero.
fn div_round(num: i64, den: i64) -> i64 {
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
    fn a_quarter_turn_is_1024_ticks() {
        // pi/2 rad = 15_707.96 units; a quarter of 4096 ticks.
        assert_eq!(angle_units_to_ticks(15_708), 1024);
        assert_eq!(angle_units_to_ticks(-15_708), -1024);
        assert_eq!(ticks_to_angle_units(1024), 15_708);
        assert_eq!(ticks_to_angle_units(-2048), -31_416);
    }

    #[test]
    fn one_tick_is_0_088_degrees() {
        // 0.088 deg = 1.5359e-3 rad = 15.36 units: 15 units round to 1 tick (0.977), 8 to 1 (0.52), 7 to 0.
        assert_eq!(ticks_to_angle_units(1), 15);
        assert_eq!(angle_units_to_ticks(8), 1);
        assert_eq!(angle_units_to_ticks(7), 0);
    }
}

//! [`Calibration`]: where a joint's zero is on its servo, which way the servo turns, and how many
//! ticks make a turn: the one angle <-> ticks converter of the project. The step table's joint map,
//! the firmware's torque bias, limits and telemetry, and the host's table building all go through
//! it, in exact integer arithmetic (no float on the board), rounding half away from zero.

use crate::gait::{ServoModel, Sign};
use crate::units::div_round;

/// 2 pi x 1e9, rounded (relative error 5e-11): ticks = urad x ticks per rev x 1000 / this.
const TWO_PI_NANO: i64 = 6_283_185_307;
/// Microradians per table angle unit (1e-4 rad).
pub const URAD_PER_ANGLE_UNIT: i32 = 100;

/// Angle <-> ticks of one joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Calibration {
    /// Servo ticks at joint angle 0.
    pub zero_ticks: i32,
    /// Whether ticks grow with the joint angle.
    pub sign: Sign,
    /// Ticks per output revolution of the servo ([`ServoModel::ticks_per_rev`]).
    pub ticks_per_rev: i32,
}

impl Calibration {
    /// The calibration of a `model` servo mounted with `zero_ticks` at joint angle 0.
    pub const fn new(model: ServoModel, zero_ticks: i32, sign: Sign) -> Self {
        Self {
            zero_ticks,
            sign,
            ticks_per_rev: model.ticks_per_rev(),
        }
    }

    /// An angle in microradians as ticks from the zero, in the joint's direction (no zero, no
    /// sign applied), unclamped. The angle is clamped to +-2^40 urad first so nothing overflows.
    pub fn urad_to_ticks(&self, urad: i64) -> i64 {
        let tpr = i64::from(self.ticks_per_rev);
        div_round(urad.clamp(-1 << 40, 1 << 40) * tpr * 1000, TWO_PI_NANO)
    }

    /// Ticks from the zero (in the joint's direction) as microradians: inverse of the above.
    pub fn ticks_to_urad(&self, ticks: i64) -> i64 {
        div_round(ticks * TWO_PI_NANO, i64::from(self.ticks_per_rev) * 1000)
    }

    /// Servo position of a joint angle in microradians: `zero + sign * urad * tpr / 2 pi`, unclamped.
    pub fn goal_of_urad(&self, urad: i64) -> i64 {
        i64::from(self.zero_ticks) + i64::from(self.sign.as_i32()) * self.urad_to_ticks(urad)
    }

    /// Servo position of a joint angle in table units (1e-4 rad), unclamped.
    ///
    /// Takes an `i32` so that a biased angle beyond the `i16` range still converts.
    pub fn angle_to_ticks(&self, angle: i32) -> i32 {
        self.goal_of_urad(i64::from(angle) * i64::from(URAD_PER_ANGLE_UNIT)) as i32
    }

    /// Ticks of `ticks` from the zero in the joint's direction, wrapped to one turn around the zero
    /// (+-half a turn), so a servo that reports a position a whole turn off still reads right.
    pub fn joint_ticks(&self, ticks: i32) -> i64 {
        let half = self.ticks_per_rev / 2;
        let delta = (ticks.wrapping_sub(self.zero_ticks).wrapping_add(half))
            .rem_euclid(self.ticks_per_rev)
            - half;
        i64::from(self.sign.as_i32()) * i64::from(delta)
    }

    /// Joint angle in table units (1e-4 rad) of a servo position, wrapped to +-pi around the zero
    /// so that it always fits an `i16`; rounded once, to nearest.
    pub fn ticks_to_angle(&self, ticks: i32) -> i16 {
        let t = self.joint_ticks(ticks);
        let per_unit = i64::from(self.ticks_per_rev) * 1000 * i64::from(URAD_PER_ANGLE_UNIT);
        div_round(t * TWO_PI_NANO, per_unit) as i16
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cal(zero: i32, sign: Sign) -> Calibration {
        Calibration::new(ServoModel::Mx28, zero, sign)
    }

    #[test]
    fn a_quarter_turn_is_1024_ticks() {
        // pi/2 rad = 15_707.96 units; a quarter of 4096 ticks.
        let c = cal(0, Sign::Positive);
        assert_eq!(c.angle_to_ticks(15_708), 1024);
        assert_eq!(c.angle_to_ticks(-15_708), -1024);
        assert_eq!(c.ticks_to_angle(1024), 15_708);
        assert_eq!(c.ticks_to_angle(-2048), -31_416);
        // With a zero and a reversed servo: 2048 - 1024.
        assert_eq!(cal(2048, Sign::Negative).angle_to_ticks(15_708), 1024);
        assert_eq!(cal(2048, Sign::Positive).angle_to_ticks(15_708), 3072);
    }

    #[test]
    fn one_tick_is_0_088_degrees() {
        // 0.088 deg = 1.5359e-3 rad = 15.36 units: 15 units round to 1 tick (0.977), 8 to 1 (0.52), 7 to 0.
        let c = cal(0, Sign::Positive);
        assert_eq!(c.ticks_to_angle(1), 15);
        assert_eq!(c.angle_to_ticks(8), 1);
        assert_eq!(c.angle_to_ticks(7), 0);
        // 1 tick = 1533.98 urad; half a tick 766.99.
        assert_eq!(c.ticks_to_urad(1), 1534);
        assert_eq!(c.urad_to_ticks(766), 0);
        assert_eq!(c.urad_to_ticks(767), 1);
    }

    #[test]
    fn positions_a_turn_off_read_as_the_same_angle() {
        // Zero at 1000, reversed: 1000 - 4096 - 100 is 100 ticks past the zero the other way.
        let c = cal(1000, Sign::Negative);
        assert_eq!(c.joint_ticks(900), 100);
        assert_eq!(c.joint_ticks(900 - 4096), 100);
        assert_eq!(c.joint_ticks(1100 + 4096), -100);
    }

    #[test]
    fn round_trip_within_half_a_tick_against_f64() {
        let c = cal(2048, Sign::Negative);
        for angle in (-31_000..31_000).step_by(7) {
            let exact = 2048.0 - f64::from(angle) * 1e-4 * 4096.0 / core::f64::consts::TAU;
            let t = c.angle_to_ticks(angle);
            assert!(
                (f64::from(t) - exact).abs() <= 0.5 + 1e-9,
                "{angle}: {t} vs {exact}"
            );
            let back = c.ticks_to_angle(t);
            // One tick is 15.34 units: back within half a tick of the angle.
            assert!(
                (i32::from(back) - angle).abs() <= 8,
                "{angle} -> {t} -> {back}"
            );
        }
    }
}

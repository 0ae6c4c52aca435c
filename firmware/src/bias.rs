//! Torque bias in fixed point: the goal a position-controlled servo must get so that, pushed by the
//! planned torque, it ends at the planned angle. A servo's P controller acts as a spring of stiffness
//! k, so goal = angle + torque / k, then into ticks with the joint's zero offset and sign, clamped to
//! the joint's limits. Units: angles in microradians, torques in mN m, stiffness in mN m / rad.
//! Angle -> ticks is the protocol's [`Calibration`], the same converter the host builds tables with.
//!
//! k is the joint's stiffness (the table's, or `SetStiffness`), and the controller makes it the
//! servo's too: it writes the servo's Position P Gain from k (`dynamixel::units::p_gain_for_stiffness`,
//! at torque-on and after every change; `controller::BusAction::WriteGains`), so the bias divides by
//! the stiffness the servo has, to within half a P unit (0.007 N m/rad on an MX-28). Stiffness 0
//! switches the bias off and leaves the servo's gain as it is (P = 0 would make it limp).

use protocol::units::div_round;
use protocol::{Calibration, ServoModel};

/// Where a joint's servo sits and how far it may go.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct JointCal {
    /// Dynamixel ID.
    pub id: u8,
    /// Servo model: its Position P Gain for the joint's stiffness
    /// (`dynamixel::units::p_gain_for_stiffness`).
    pub model: ServoModel,
    /// Angle <-> ticks (zero, direction, ticks per turn).
    pub calibration: Calibration,
    /// Lowest allowed goal, in ticks.
    pub min_ticks: i32,
    /// Highest allowed goal, in ticks.
    pub max_ticks: i32,
    /// The leg the joint belongs to (0 ..= 5 in LF, LM, LH, RF, RM, RH), if the table says: the
    /// start ramp lifts a leg's joints together ([`crate::playback::start_lifts`]).
    pub leg: Option<u8>,
}

/// Bias angle torque / k in microradians; no bias when `stiffness` is 0 (bias switched off).
pub fn bias_urad(torque_mnm: i32, stiffness_mnm_per_rad: u32) -> i64 {
    if stiffness_mnm_per_rad == 0 {
        return 0;
    }
    div_round(torque_mnm as i64 * 1_000_000, stiffness_mnm_per_rad as i64)
}

/// Goal position in ticks for the planned `angle_urad` and `torque_mnm` at `stiffness`, clamped to
/// the joint's limits. Returns the goal and whether the clamp cut it.
pub fn goal_ticks(
    cal: &JointCal,
    angle_urad: i32,
    torque_mnm: i32,
    stiffness_mnm_per_rad: u32,
) -> (i32, bool) {
    let joint = angle_urad as i64 + bias_urad(torque_mnm, stiffness_mnm_per_rad);
    let ticks = cal.calibration.goal_of_urad(joint);
    let clamped = ticks.clamp(cal.min_ticks as i64, cal.max_ticks as i64);
    (clamped as i32, clamped != ticks)
}

#[cfg(test)]
mod tests {
    use super::*;
    use protocol::Sign;

    fn calibration(zero_ticks: i32, sign: i8) -> Calibration {
        let sign = if sign < 0 {
            Sign::Negative
        } else {
            Sign::Positive
        };
        Calibration::new(ServoModel::Mx28, zero_ticks, sign)
    }

    /// The same formula in f64, written from the physics: theta + tau / k, in revolutions x 4096.
    /// Unclamped goal in ticks.
    fn reference(cal: &JointCal, angle_urad: i32, torque_mnm: i32, k: u32) -> f64 {
        let theta = angle_urad as f64 * 1e-6;
        let bias = if k == 0 {
            0.0
        } else {
            (torque_mnm as f64 * 1e-3) / (k as f64 * 1e-3)
        };
        cal.calibration.zero_ticks as f64
            + cal.calibration.sign.as_i32() as f64 * (theta + bias) * 4096.0
                / (2.0 * std::f64::consts::PI)
    }

    #[test]
    fn hand_calculated_cases() {
        let cal = JointCal {
            id: 1,
            model: ServoModel::Mx28,
            calibration: calibration(2048, 1),
            min_ticks: 0,
            max_ticks: 4095,
            leg: None,
        };
        // pi/2 rad is a quarter turn: 1024 ticks.
        assert_eq!(goal_ticks(&cal, 1_570_796, 0, 8400), (2048 + 1024, false));
        // 0.84 N m on an 8.4 N m/rad spring deflects 0.1 rad = 65.19 ticks -> 65.
        assert_eq!(goal_ticks(&cal, 0, 840, 8400), (2048 + 65, false));
        // Reversed servo, negative torque: -(-0.1 rad) = +65 ticks.
        let rev = JointCal {
            calibration: calibration(2048, -1),
            ..cal
        };
        assert_eq!(goal_ticks(&rev, 0, -840, 8400), (2048 + 65, false));
        // Stiffness 0 switches the bias off.
        assert_eq!(goal_ticks(&cal, 0, 840, 0), (2048, false));
        // A full turn past the limit is clamped, and says so.
        assert_eq!(goal_ticks(&cal, 6_283_185, 0, 8400), (4095, true));
        assert_eq!(goal_ticks(&rev, 6_283_185, 0, 8400), (0, true));
    }

    #[test]
    fn fixed_point_agrees_with_the_f64_formula_on_random_inputs() {
        // A fixed seed: the same inputs every run.
        let mut rng = fastrand::Rng::with_seed(0x9E37_79B9_7F4A_7C15);
        let mut exact = 0;
        let n = 200_000;
        for _ in 0..n {
            let min = rng.i32(0..=2047);
            let cal = JointCal {
                id: 1,
                model: ServoModel::Mx28,
                calibration: calibration(rng.i32(0..=4095), if rng.bool() { 1 } else { -1 }),
                min_ticks: min,
                max_ticks: min + rng.i32(1..=2048),
                leg: None,
            };
            let angle = rng.i32(-3_141_593..=3_141_593);
            let torque = rng.i32(-6000..=6000);
            let k = if rng.u32(..50) == 0 {
                0
            } else {
                rng.u32(500..=30_000)
            };
            let free = reference(&cal, angle, torque, k);
            let want = free.clamp(cal.min_ticks as f64, cal.max_ticks as f64);
            let (got, clamped) = goal_ticks(&cal, angle, torque, k);
            // Two roundings (bias to 1 urad, ticks to 1 tick) may move a result across a half tick:
            // never more than one tick off.
            assert!(
                (got as f64 - want).abs() <= 1.0,
                "{cal:?} angle {angle} torque {torque} k {k}: {got} vs {want}"
            );
            if got as f64 == want.round() {
                exact += 1;
            }
            // The clamp flag is set exactly when the goal left the limits (give or take the rounding).
            if free < cal.min_ticks as f64 - 1.0 || free > cal.max_ticks as f64 + 1.0 {
                assert!(
                    clamped,
                    "{free} outside {}..{}",
                    cal.min_ticks, cal.max_ticks
                );
            }
            if free > cal.min_ticks as f64 + 1.0 && free < cal.max_ticks as f64 - 1.0 {
                assert!(
                    !clamped,
                    "{free} inside {}..{}",
                    cal.min_ticks, cal.max_ticks
                );
            }
        }
        // Off by one only within a hair of a half tick: rare.
        assert!(exact > n * 999 / 1000, "{exact} of {n} exact");
    }

    #[test]
    fn ticks_and_microradians_round_trip_within_half_a_tick() {
        let c = calibration(0, 1);
        for t in [-4096i64, -1, 0, 1, 1024, 2048, 4095] {
            assert_eq!(c.urad_to_ticks(c.ticks_to_urad(t)), t);
        }
        // 1 tick = 2 pi / 4096 rad = 1533.98 urad.
        assert_eq!(c.ticks_to_urad(1), 1534);
    }
}

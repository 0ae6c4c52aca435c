//! The MX servo as MuJoCo sees it, and the conversions between its control table and the joint.
//!
//! The MJCF's position actuator is `kp (ctrl - q) - kv qdot`, limited to the stall torque, with kp
//! the model's stiffness (the number the firmware's torque bias divides by) and kv the slope of
//! the DC motor's torque-speed line (stall torque / no-load speed). The MX's P controller saturates
//! its PWM duty, not its torque: [`ctrl`] clamps the position error to the stall torque's worth
//! before MuJoCo adds the damping, so the actuator is `stall * (clamp(duty) - qdot / omega_0)`, the
//! motor model of the dynamixel crate's virtual servo, and a saturated servo cannot outrun its
//! no-load speed. The velocity term stays inside MuJoCo, integrated implicitly (implicitfast).

use dynamixel::ServoModel;
use dynamixel::sim::physics::MotorState;
use planner::model::ServoMap;

/// Radians per servo tick (4096 ticks a turn), f64.
pub const RAD_PER_TICK: f64 = std::f64::consts::TAU / 4096.0;

/// The actuator's stiffness, N m/rad, for a Position P Gain register value: the MX's conversion
/// (`dynamixel::units::stiffness_nm_per_rad`, an ESTIMATE from the e-manual's P controller), the
/// one the physics robot reads its servos' gains with.
pub fn stiffness_of_p_gain(model: ServoModel, p_gain: u16) -> f64 {
    f64::from(dynamixel::units::stiffness_nm_per_rad(model, p_gain))
}

/// The Position P Gain register value nearest to stiffness `kp` N m/rad: the firmware's own
/// conversion ([`dynamixel::units::p_gain_for_stiffness`], the inverse of
/// [`stiffness_of_p_gain`]; saturated to the register's range, at least 1 for a positive `kp`).
pub fn p_gain_for_stiffness(model: ServoModel, kp: f64) -> u16 {
    dynamixel::units::p_gain_for_stiffness(model, kp as f32)
}

/// Joint angle (rad) of a goal or present position in ticks, through the model's servo map and
/// the project's one converter ([`ServoMap::angle_of_ticks`], `protocol::Calibration`).
pub fn ticks_to_angle(map: &ServoMap, ticks: i32) -> f64 {
    map.angle_of_ticks(ticks)
}

/// The motor state a servo reports for its joint's angle, velocity and actuator torque: angle from
/// tick 0 and velocity and torque toward increasing ticks, as the virtual servo keeps them.
pub fn motor_state(map: &ServoMap, q: f64, qd: f64, torque: f64, duty: f64) -> MotorState {
    let sign = f64::from(map.sign);
    let centre = f64::from(map.centre_calibration().zero_ticks);
    let rad_per_tick = std::f64::consts::TAU / f64::from(map.model.ticks_per_rev());
    MotorState {
        angle_rad: sign * (q - map.zero_offset) + centre * rad_per_tick,
        velocity_rad_s: sign * qd,
        torque_nm: sign * torque,
        duty: sign * duty,
    }
}

/// The position actuator's control for one step: the goal, or with torque off the present angle
/// (no spring; the motor still brakes through kv). The error is clamped to what the stall torque
/// buys at stiffness `kp`: the P controller's duty saturation.
pub fn ctrl(q: f64, goal: f64, torque_on: bool, kp: f64, stall: f64) -> f64 {
    if !torque_on || kp <= 0.0 {
        return q;
    }
    let reach = stall / kp;
    q + (goal - q).clamp(-reach, reach)
}

/// PWM duty (-1..=1) the P controller outputs for this error.
pub fn duty(q: f64, goal: f64, torque_on: bool, kp: f64, stall: f64) -> f64 {
    if !torque_on {
        return 0.0;
    }
    (kp * (goal - q) / stall).clamp(-1.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map(sign: i8, zero: f64) -> ServoMap {
        ServoMap {
            id: 1,
            model: ServoModel::Mx28,
            zero_offset: zero,
            sign,
        }
    }

    #[test]
    fn ticks_and_angles_follow_the_models_servo_map() {
        // 1024 ticks past the centre is a quarter turn; a reversed servo turns the other way.
        let m = map(1, 0.1);
        // To the microradian: the one converter (protocol::Calibration) rounds there.
        assert!((ticks_to_angle(&m, 3072) - (std::f64::consts::FRAC_PI_2 + 0.1)).abs() < 1e-6);
        let r = map(-1, 0.0);
        assert!((ticks_to_angle(&r, 3072) + std::f64::consts::FRAC_PI_2).abs() < 1e-6);
        // e-manual: one tick is 0.088 deg (360 / 4096 = 0.087 890 6 deg).
        let one = ticks_to_angle(&map(1, 0.0), 2049);
        assert!((one.to_degrees() - 0.087_890_6).abs() < 1e-4, "{one}");
        // The state the servo reports for that angle lies at 3072 ticks either way.
        let s = motor_state(&r, -std::f64::consts::FRAC_PI_2, 1.0, 0.5, 0.0);
        assert!((s.angle_rad / RAD_PER_TICK - 3072.0).abs() < 1e-9);
        assert_eq!((s.velocity_rad_s, s.torque_nm), (-1.0, -0.5));
    }

    #[test]
    fn p_gain_and_stiffness_convert_both_ways() {
        // e-manual: Kp = P/128 on the error in ticks, 885 = full PWM, torque = duty * stall:
        // MX-28 at P 850: 850/128/885 * 2.5 N m * 4096/(2 pi) rad^-1 = 12.23 N m/rad.
        let k = stiffness_of_p_gain(ServoModel::Mx28, 850);
        let hand = 850.0 / 128.0 / 885.0 * 2.5 * 4096.0 / std::f64::consts::TAU;
        assert!((k - hand).abs() < 1e-4 * hand, "{k} against {hand}");
        assert_eq!(p_gain_for_stiffness(ServoModel::Mx28, hand), 850);
        // Half the gain, half the stiffness.
        let half = stiffness_of_p_gain(ServoModel::Mx28, 425);
        assert!((half - k / 2.0).abs() < 1e-9 * k);
        assert_eq!(p_gain_for_stiffness(ServoModel::Mx28, 1e-9), 1);
    }

    #[test]
    fn the_error_saturates_at_the_stall_torque() {
        // kp 14.3 N m/rad, stall 2.5 N m: at most 0.1748 rad of error counts.
        let c = ctrl(0.0, 1.0, true, 14.3, 2.5);
        assert!((c - 2.5 / 14.3).abs() < 1e-12);
        assert_eq!(ctrl(0.3, 0.35, true, 14.3, 2.5), 0.35);
        assert_eq!(ctrl(0.3, 1.0, false, 14.3, 2.5), 0.3);
        assert_eq!(duty(0.0, 1.0, true, 14.3, 2.5), 1.0);
        assert!((duty(0.0, 0.05, true, 14.3, 2.5) - 0.286).abs() < 1e-12);
    }
}

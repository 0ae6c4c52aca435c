//! The MX servo as MuJoCo sees it, and the conversions between its control table and the joint.
//!
//! The MJCF's position actuator is `kp (ctrl - q) - kv qdot`, limited to the stall torque, with kp
//! the model's stiffness (the number the firmware's torque bias divides by) and kv the slope of
//! the DC motor's torque-speed line (stall torque / no-load speed). The MX's P controller saturates
//! its PWM duty, not its torque: [`ctrl`] clamps the position error to the stall torque's worth
//! before MuJoCo adds the damping, so the actuator is `stall * (clamp(duty) - qdot / omega_0)`, the
//! motor model of the dynamixel crate's virtual servo, and a saturated servo cannot outrun its
//! no-load speed. The velocity term stays inside MuJoCo, integrated implicitly (implicitfast).
//! [`ctrl`] and [`duty`] are that ideal P servo; the plant steps the full law of the model's
//! servo dynamics ([`crate::drive`]: deadband, I and D gains, backlash), which is this one when
//! they are zero. The gain registers convert through the model's servo dynamics
//! ([`gains_of_registers`]) and the Present Load register is what [`present_load`] reports.

use dynamixel::ServoModel;
use dynamixel::sim::physics::MotorState;
use planner::model::{ServoMap, ServoParams};

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

/// Proportional, integral and derivative gains (N m/rad, N m/(rad s), N m s/rad) of the Position
/// P, I and D Gain registers of a servo with dynamics `params`: the e-manual's Kp = P / 128,
/// Ki = I / 65536 and Kd = D / 16 (PWM per tick of error, per tick-period, per tick per
/// period) times the stall torque per full PWM and ticks per radian, over the PID period
/// ([`crate::drive::PID_PERIOD_S`], an ESTIMATE). P goes through [`stiffness_of_p_gain`], scaled
/// by the model's `p_gain_divisor` (128 on the e-manual) and stall torque (the datasheet's):
/// with the defaults the very value the physics robot always used.
pub fn gains_of_registers(
    model: ServoModel,
    params: &ServoParams,
    p: u16,
    i: u16,
    d: u16,
) -> (f64, f64, f64) {
    let datasheet = f64::from(model.stall_torque_nm());
    let torque_scale = params.stall_torque_nm / datasheet;
    let kp = stiffness_of_p_gain(model, p)
        * (f64::from(dynamixel::model::P_GAIN_DIVISOR) / params.p_gain_divisor)
        * torque_scale;
    // N m per tick of error at full duty per unit of gain.
    let per_unit = params.stall_torque_nm / f64::from(dynamixel::model::PWM_FULL_SCALE)
        * f64::from(model.ticks_per_rev())
        / std::f64::consts::TAU;
    let period = crate::drive::PID_PERIOD_S;
    let ki = f64::from(i) / f64::from(dynamixel::model::I_GAIN_DIVISOR) * per_unit / period;
    let kd = f64::from(d) / f64::from(dynamixel::model::D_GAIN_DIVISOR) * per_unit * period;
    (kp, ki, kd)
}

/// Register 126 (Present Load on the MX-28, Present Current on the MX-64) a servo with dynamics
/// `params` reports for output torque `torque_nm` (servo direction): `load_gain x torque +
/// load_offset_nm + load_noise_nm x normal` through the register's conversion
/// ([`dynamixel::units::torque_to_load`], an ESTIMATE), then rounded to a multiple of
/// `load_resolution_counts` (within the register's range). `normal` is a standard normal sample
/// (anything without noise). With the defaults, exactly the conversion.
pub fn present_load(model: ServoModel, params: &ServoParams, torque_nm: f64, normal: f64) -> i16 {
    let mut t = params.load_gain * torque_nm + params.load_offset_nm;
    if params.load_noise_nm > 0.0 {
        t += params.load_noise_nm * normal;
    }
    let raw = dynamixel::units::torque_to_load(model, t as f32);
    let res = i32::from(params.load_resolution_counts.max(1));
    if res == 1 {
        return raw;
    }
    let limit = if model.reports_current() {
        i32::from(i16::MAX)
    } else {
        1000
    };
    let stepped = (f64::from(raw) / f64::from(res)).round() as i32 * res;
    // The largest multiple of the resolution within the range, on either side.
    let top = limit / res * res;
    stepped.clamp(-top, top) as i16
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
    fn the_gain_registers_convert_through_the_models_servo_dynamics() {
        let mx28 = ServoParams::defaults(ServoModel::Mx28);
        // Defaults: P 850 is the e-manual's 12.23 N m/rad, bit for bit the plain conversion.
        let (kp, ki, kd) = gains_of_registers(ServoModel::Mx28, &mx28, 850, 0, 0);
        assert_eq!(kp, stiffness_of_p_gain(ServoModel::Mx28, 850));
        assert_eq!((ki, kd), (0.0, 0.0));
        // Divisor 256 (BAM's X-series finding) halves it; a stall torque of 2.0 N m scales it
        // by 0.8.
        let soft = ServoParams {
            p_gain_divisor: 256.0,
            stall_torque_nm: 2.0,
            ..mx28
        };
        let (kp2, _, _) = gains_of_registers(ServoModel::Mx28, &soft, 850, 0, 0);
        assert!((kp2 - kp * 0.5 * 0.8).abs() < 1e-12 * kp);
        // I 65536/1000 would be a whole PWM unit per tick per ms... take I = 1000, D = 16:
        // per unit 2.5 / 885 x 4096 / 2 pi = 1.8415 N m/rad; ki = 1000/65536 x 1.8415 / 1 ms =
        // 28.10 N m/(rad s); kd = 1 x 1.8415 x 1 ms = 1.8415e-3 N m s/rad.
        let (_, ki, kd) = gains_of_registers(ServoModel::Mx28, &mx28, 850, 1000, 16);
        let unit = 2.5 / 885.0 * 4096.0 / std::f64::consts::TAU;
        assert!((ki - 1000.0 / 65536.0 * unit / 1e-3).abs() < 1e-9, "{ki}");
        assert!((kd - unit * 1e-3).abs() < 1e-12, "{kd}");
    }

    #[test]
    fn present_load_applies_gain_offset_resolution_and_noise() {
        let mx28 = ServoParams::defaults(ServoModel::Mx28);
        // Defaults: the register's own conversion (0.1 % of 2.5 N m per count).
        for t in [-3.0, -1.2345, 0.0, 0.5, 2.4] {
            assert_eq!(
                present_load(ServoModel::Mx28, &mx28, t, 0.0),
                dynamixel::units::torque_to_load(ServoModel::Mx28, t as f32)
            );
        }
        // Gain 0.8, offset 0.1 N m: 1.0 N m reads as 0.9 N m = 360 counts; resolution 8 counts
        // puts it on 360 (45 x 8); 1.01 N m -> 0.908 N m = 363.2 -> 363 counts -> 360; 1.03 N m
        // -> 0.924 N m = 369.6 -> 370 counts -> 368.
        let p = ServoParams {
            load_gain: 0.8,
            load_offset_nm: 0.1,
            load_resolution_counts: 8,
            ..mx28
        };
        assert_eq!(present_load(ServoModel::Mx28, &p, 1.0, 0.0), 360);
        assert_eq!(present_load(ServoModel::Mx28, &p, 1.01, 0.0), 360);
        assert_eq!(present_load(ServoModel::Mx28, &p, 1.03, 0.0), 368);
        // Beyond the MX-28's +-1000: the largest multiple of 8 within it.
        assert_eq!(present_load(ServoModel::Mx28, &p, 10.0, 0.0), 1000);
        assert_eq!(present_load(ServoModel::Mx28, &p, -10.0, 0.0), -1000);
        // Noise 0.05 N m at a sample of 2 standard deviations: +0.1 N m = +40 counts.
        let n = ServoParams {
            load_noise_nm: 0.05,
            ..mx28
        };
        assert_eq!(present_load(ServoModel::Mx28, &n, 1.0, 2.0), 440);
        // Without noise the sample changes nothing.
        assert_eq!(present_load(ServoModel::Mx28, &mx28, 1.0, 2.0), 400);
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

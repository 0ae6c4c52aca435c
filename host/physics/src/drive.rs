//! The physics servo's control law, one MuJoCo step at a time: the deadband, the PID of the gain
//! registers, the PWM saturation at the stall torque, and the gear train's backlash. Pure
//! functions of the joint's state and the servo's [`DriveState`]; [`crate::plant::Plant`] turns
//! them into the position actuator's control and switches the actuator off while the backlash
//! is open.
//!
//! The actuator is MuJoCo's position actuator `kp (ctrl - q) - kv qdot`, limited to the stall
//! torque, with `kv` the torque-speed line's slope (stall / no-load speed). The controller's
//! drive in N m is `u = kp e + ki integral(e) + kd de/dt` on the error `e` past the deadband;
//! the PWM duty is `u / stall` clamped to +-1 and [`Drive::ctrl`] puts the position actuator at
//! `stall duty - kv qdot`: the motor's torque-speed line, saturated.
//!
//! Backlash `b`: the motor side sits within `+-b/2` of the output (`gap` = motor - output). At
//! `+b/2` the gears touch on the side that pushes the output forward, so they carry a force
//! only if it is positive; at `-b/2`, only a negative one. Otherwise the gears are apart, the
//! output feels no actuator force, and the unloaded motor turns at `duty x no-load speed` until
//! it closes the gap. With `b = 0` the gears never part and the law is the ideal P servo's.

/// The servo's PID period, s: the time unit of the I and D gains (Ki = I / 65536 per tick of
/// error per period, Kd = D / 16 per tick of error change per period). ESTIMATE 1 ms: the
/// e-manual gives no rate for the MX position loop.
pub const PID_PERIOD_S: f64 = 0.001;

/// The gains and limits of one servo, SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gains {
    /// Proportional gain (the stiffness), N m/rad.
    pub kp: f64,
    /// Integral gain, N m/(rad s).
    pub ki: f64,
    /// Derivative gain, N m s/rad.
    pub kd: f64,
    /// Stall torque, N m (the PWM saturation and the actuator's force limit).
    pub stall: f64,
    /// The torque-speed line's slope, N m s/rad (stall / no-load speed).
    pub kv: f64,
    /// Deadband, rad.
    pub deadband: f64,
    /// Backlash (total play), rad.
    pub backlash: f64,
}

impl Gains {
    /// No-load speed, rad/s.
    pub fn no_load_speed(&self) -> f64 {
        self.stall / self.kv
    }
}

/// What the servo remembers between steps.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DriveState {
    /// Integral of the error past the deadband, rad s (0 while the torque is off).
    pub integral: f64,
    /// The previous step's error, rad (none after torque-on).
    pub last_error: Option<f64>,
    /// Motor side minus output, rad, within +-backlash/2.
    pub gap: f64,
}

/// One step's command.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drive {
    /// The position actuator's control, rad.
    pub ctrl: f64,
    /// PWM duty, -1..=1.
    pub duty: f64,
    /// The error past the deadband, rad.
    pub error: f64,
    /// The integral and derivative terms, N m (0 with no I or D gain).
    pub extra: f64,
    /// Whether the gears carry the actuator's force to the output.
    pub engaged: bool,
}

/// The error the controller acts on: 0 within the deadband, else the error less the deadband.
pub fn past_deadband(error: f64, deadband: f64) -> f64 {
    if deadband <= 0.0 {
        error
    } else if error.abs() <= deadband {
        0.0
    } else {
        error - deadband.copysign(error)
    }
}

/// The controller's drive beyond the proportional term, N m: the integral (its torque clamped to
/// the stall torque, against wind-up) and the derivative of the error over the step `h`.
fn integral_and_derivative(g: &Gains, s: &DriveState, error: f64, h: f64) -> f64 {
    if g.ki == 0.0 && g.kd == 0.0 {
        return 0.0;
    }
    let rate = s.last_error.map_or(0.0, |last| (error - last) / h);
    (g.ki * s.integral).clamp(-g.stall, g.stall) + g.kd * rate
}

/// The command for a step of `h` s at angle `q` and velocity `qd` toward `goal`: with the torque
/// off the actuator only brakes (ctrl = q, duty 0). Inlined into the plant's step (22 joints,
/// every MuJoCo step).
#[inline]
pub fn drive(
    q: f64,
    qd: f64,
    goal: f64,
    torque_on: bool,
    g: &Gains,
    s: &DriveState,
    h: f64,
) -> Drive {
    let (ctrl, duty, error, extra) = if !torque_on || g.kp <= 0.0 {
        (q, 0.0, 0.0, 0.0)
    } else {
        let e = past_deadband(goal - q, g.deadband);
        let extra = integral_and_derivative(g, s, e, h);
        let reach = g.stall / g.kp;
        let ctrl = q + (e + extra / g.kp).clamp(-reach, reach);
        (ctrl, duty_of(g.kp * e + extra, g.stall), e, extra)
    };
    let force = g.stall * duty - g.kv * qd;
    Drive {
        ctrl,
        duty,
        error,
        extra,
        engaged: engaged(s.gap, force, g.backlash),
    }
}

/// PWM duty of a drive `u` N m: `u / stall`, clamped to +-1.
pub fn duty_of(u: f64, stall: f64) -> f64 {
    (u / stall).clamp(-1.0, 1.0)
}

/// Whether gears `gap` apart (motor - output) carry `force` (N m on the output) with `backlash`.
pub fn engaged(gap: f64, force: f64, backlash: f64) -> bool {
    if backlash <= 0.0 {
        return true;
    }
    let half = 0.5 * backlash;
    (gap >= half && force > 0.0) || (gap <= -half && force < 0.0)
}

/// The servo's memory after a step of `h` s that `d` commanded with the output at velocity `qd`
/// over it: the integral and last error while the torque is on, and an open gap closing at the
/// free motor's speed (duty x no-load speed) less the output's.
#[inline]
pub fn advance(s: &mut DriveState, d: &Drive, torque_on: bool, qd: f64, g: &Gains, h: f64) {
    if torque_on {
        if g.ki != 0.0 {
            s.integral += d.error * h;
        }
        s.last_error = Some(d.error);
    } else {
        s.integral = 0.0;
        s.last_error = None;
    }
    if g.backlash > 0.0 && !d.engaged {
        let half = 0.5 * g.backlash;
        s.gap = (s.gap + (d.duty * g.no_load_speed() - qd) * h).clamp(-half, half);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gains(backlash: f64, deadband: f64) -> Gains {
        // An MX-28 at 14.3 N m/rad: stall 2.5 N m, no-load speed 5.76 rad/s.
        Gains {
            kp: 14.3,
            ki: 0.0,
            kd: 0.0,
            stall: 2.5,
            kv: 2.5 / 5.76,
            deadband,
            backlash,
        }
    }

    #[test]
    fn a_goal_inside_the_deadband_gives_no_torque() {
        // Deadband 0.01 rad: a goal 0.008 rad away is no error at all; 0.03 rad away counts as
        // 0.02 rad (continuous at the band's edge), either direction.
        let g = gains(0.0, 0.01);
        let s = DriveState::default();
        let d = drive(0.5, 0.0, 0.508, true, &g, &s, 1e-3);
        assert_eq!((d.ctrl, d.duty, d.error), (0.5, 0.0, 0.0));
        let d = drive(0.5, 0.0, 0.53, true, &g, &s, 1e-3);
        assert!((d.error - 0.02).abs() < 1e-12);
        assert!((d.duty - 14.3 * 0.02 / 2.5).abs() < 1e-12);
        let d = drive(0.5, 0.0, 0.47, true, &g, &s, 1e-3);
        assert!((d.error + 0.02).abs() < 1e-12);
        assert_eq!(past_deadband(0.01, 0.01), 0.0);
        // No deadband: the error is the error, bit for bit (the ideal P servo).
        assert_eq!(past_deadband(0.123, 0.0), 0.123);
    }

    #[test]
    fn the_drive_saturates_on_the_torque_speed_line() {
        // Far from the goal the duty is 1; the actuator's control puts kp (ctrl - q) at the
        // stall torque, and the force at speed w is stall - kv w = stall (1 - w / w0).
        let g = gains(0.0, 0.0);
        let d = drive(0.0, 2.0, 1.0, true, &g, &DriveState::default(), 1e-3);
        assert_eq!(d.duty, 1.0);
        assert!((g.kp * (d.ctrl - 0.0) - 2.5).abs() < 1e-12);
        let force = g.kp * (d.ctrl - 0.0) - g.kv * 2.0;
        assert!((force - 2.5 * (1.0 - 2.0 / 5.76)).abs() < 1e-12);
    }

    #[test]
    fn a_reversal_crosses_the_backlash_before_the_output_is_driven() {
        // Backlash 0.01 rad, the motor pushing the output forward (gap +0.005). The goal
        // reverses to 0.2 rad behind: duty -1 (14.3 x 0.2 > 2.5), the gears part, and the free
        // motor turns back at the no-load speed 5.76 rad/s: 0.01 rad in 1.736 ms, so with the
        // output still, steps of 0.5 ms are apart for 4 steps (2 ms > 1.736 ms) and then touch.
        let g = gains(0.01, 0.0);
        let h = 0.5e-3;
        let mut s = DriveState {
            gap: 0.005,
            ..DriveState::default()
        };
        let forward = drive(0.0, 0.0, 0.1, true, &g, &s, h);
        assert!(forward.engaged, "pushing forward at +b/2 drives the output");
        let mut apart = 0;
        loop {
            let d = drive(0.0, 0.0, -0.2, true, &g, &s, h);
            if d.engaged {
                break;
            }
            assert_eq!(d.duty, -1.0);
            apart += 1;
            advance(&mut s, &d, true, 0.0, &g, h);
            assert!(apart < 100);
        }
        assert_eq!(apart, 4);
        assert_eq!(s.gap, -0.005);
        // An output moving backward faster than the free motor leaves the gears apart.
        let s = DriveState {
            gap: -0.005,
            ..DriveState::default()
        };
        assert!(!drive(0.0, -7.0, -0.2, true, &g, &s, h).engaged);
        // No backlash: always engaged.
        assert!(engaged(0.0, 0.0, 0.0));
    }

    #[test]
    fn the_integral_and_derivative_follow_the_registers_units() {
        // ki 10 N m/(rad s) over an error of 0.01 rad held 0.1 s adds 0.01 N m; kd 0.1 N m s/rad on
        // an error falling 0.001 rad per 1 ms step subtracts 0.1 N m.
        let mut g = gains(0.0, 0.0);
        g.ki = 10.0;
        let h = 1e-3;
        let mut s = DriveState::default();
        for _ in 0..100 {
            let d = drive(0.0, 0.0, 0.01, true, &g, &s, h);
            advance(&mut s, &d, true, 0.0, &g, h);
        }
        assert!((s.integral - 0.001).abs() < 1e-12);
        let d = drive(0.0, 0.0, 0.01, true, &g, &s, h);
        assert!((d.duty - (14.3 * 0.01 + 0.01) / 2.5).abs() < 1e-12);
        let mut g = gains(0.0, 0.0);
        g.kd = 0.1;
        let s = DriveState {
            last_error: Some(0.011),
            ..DriveState::default()
        };
        let d = drive(0.0, 0.0, 0.01, true, &g, &s, h);
        assert!((d.duty - (14.3 * 0.01 - 0.1) / 2.5).abs() < 1e-12);
        // Torque off forgets both.
        let mut s = s;
        advance(&mut s, &d, false, 0.0, &g, h);
        assert_eq!((s.integral, s.last_error), (0.0, None));
    }
}

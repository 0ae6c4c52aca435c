//! The virtual servo's motor: a quasi-static DC motor behind the MX position P controller.
//!
//! Model (all an ESTIMATE; ROBOTIS publishes only performance graphs):
//! - PWM duty d = clamp(Kp * error_ticks / 885, -1, 1) with Kp = P gain / 128 (e-manual), i.e. a
//!   spring of stiffness [`crate::units::stiffness_nm_per_rad`] up to saturation.
//! - Motor torque at the output tau_m = tau_stall * (d - omega / omega_0), the linear torque-speed
//!   line of a DC motor through the stall torque and the no-load speed omega_0 (datasheet, 12 V).
//! - The rotor and gear inertia are neglected (quasi-static): tau_m + tau_ext = 0, hence
//!   omega = omega_0 * (d + tau_ext / tau_stall). Near the goal this is a first-order lag with
//!   time constant tau_stall / (omega_0 * k), about 35 ms for an MX-28 at P = 850, and the
//!   equilibrium is offset by tau_ext / k like a spring. The speed limit is the no-load speed
//!   (reduced by load, as on the datasheet's curve).
//! - Torque off: d = 0, the output is back-driven through the motor's back-EMF.
//! - Stuck: omega = 0 and the motor delivers tau_stall * d (what a stalled motor does).

use crate::model::ServoModel;
use crate::units::{PWM_FULL_SCALE, RAD_PER_TICK};

/// Motor state of one servo, SI units, angle measured from tick 0.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MotorState {
    pub angle_rad: f64,
    pub velocity_rad_s: f64,
    /// Torque the servo delivers at its output, N m, positive toward increasing ticks.
    pub torque_nm: f64,
    /// PWM duty -1..=1.
    pub duty: f64,
}

/// Inputs of one integration step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotorInput {
    pub model: ServoModel,
    pub torque_on: bool,
    pub goal_ticks: i32,
    pub p_gain: u16,
    /// External load torque at the output, N m, positive toward increasing ticks.
    pub external_nm: f64,
    pub stuck: bool,
}

fn duty(input: &MotorInput, angle_rad: f64) -> f64 {
    if !input.torque_on {
        return 0.0;
    }
    let error_ticks = input.goal_ticks as f64 - angle_rad / RAD_PER_TICK as f64;
    (input.p_gain as f64 / 128.0 * error_ticks / PWM_FULL_SCALE as f64).clamp(-1.0, 1.0)
}

fn velocity(input: &MotorInput, d: f64) -> f64 {
    if input.stuck {
        return 0.0;
    }
    let stall = input.model.stall_torque_nm() as f64;
    let omega0 = input.model.no_load_speed_rad_s() as f64;
    omega0 * (d + input.external_nm / stall)
}

/// Advances `state` by `dt_s` seconds.
pub fn step(state: &mut MotorState, input: &MotorInput, dt_s: f64) {
    let stall = input.model.stall_torque_nm() as f64;
    let omega0 = input.model.no_load_speed_rad_s() as f64;
    // Sub-steps well below the loop's time constant keep explicit Euler stable at any P gain.
    let k_ticks = (input.p_gain.max(1) as f64 / 128.0) / PWM_FULL_SCALE as f64;
    let tau = 1.0 / (omega0 * k_ticks / RAD_PER_TICK as f64);
    let max_sub = (tau / 5.0).min(1e-3);
    let mut left = dt_s.max(0.0);
    while left > 0.0 {
        let h = left.min(max_sub);
        let d = duty(input, state.angle_rad);
        let w = velocity(input, d);
        state.angle_rad += w * h;
        left -= h;
    }
    let d = duty(input, state.angle_rad);
    let w = velocity(input, d);
    state.velocity_rad_s = w;
    state.duty = d;
    state.torque_nm = stall * (d - w / omega0);
}

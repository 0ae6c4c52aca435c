//! The servo-dynamics parameters the identification fits from motion (present position and
//! velocity), each with its bounds, the scale the optimiser sees it in and its finite-difference
//! step; and those it does not fit from motion, with the reason
//! ([`NOT_FROM_MOTION`]). The Present Load reading (gain, offset, resolution, noise) is fitted
//! afterwards from the load alone ([`super::load`]).

use planner::model::{ServoParams, ServoParamsEntry};

/// One fitted parameter.
#[derive(Debug, Clone, Copy)]
pub struct Fitted {
    /// The model file's field name.
    pub name: &'static str,
    pub unit: &'static str,
    /// Bounds the fit keeps within (value units).
    pub lo: f64,
    pub hi: f64,
    /// The optimiser sees `value / scale` (every parameter of order 1).
    pub scale: f64,
    /// Finite-difference step, value units.
    pub step: f64,
    pub get: fn(&ServoParams) -> f64,
    pub set: fn(&mut ServoParamsEntry, f64),
}

/// Radians per tick of a 4096-tick servo.
const TICK: f64 = std::f64::consts::TAU / 4096.0;

/// A [`Fitted`] of the model file's field `$field` (its name, getter and setter from the one
/// identifier): unit, bounds, scale and step.
macro_rules! fitted {
    ($field:ident, $unit:expr, $lo:expr, $hi:expr, $scale:expr, $step:expr) => {
        Fitted {
            name: stringify!($field),
            unit: $unit,
            lo: $lo,
            hi: $hi,
            scale: $scale,
            step: $step,
            get: |p| p.$field,
            set: |e, v| e.$field = Some(v),
        }
    };
}

/// The parameters fitted from motion, in this order: field, unit, bounds (lo, hi), scale, step.
pub const MOTION: &[Fitted] = &[
    fitted!(p_gain_divisor, "", 32.0, 1024.0, 100.0, 2.0),
    fitted!(stall_torque_nm, "N m", 0.2, 20.0, 1.0, 0.05),
    fitted!(damping_nm_s_per_rad, "N m s/rad", 0.0, 1.0, 0.01, 0.002),
    fitted!(friction_nm, "N m", 0.0, 0.5, 0.01, 0.003),
    fitted!(armature_kg_m2, "kg m^2", 0.0, 0.05, 1e-3, 3e-4),
    fitted!(deadband_rad, "rad", 0.0, 0.02, TICK, 0.5 * TICK),
    fitted!(backlash_rad, "rad", 0.0, 0.02, TICK, 0.5 * TICK),
];

/// The servo-dynamics fields not fitted from motion, and why.
pub const NOT_FROM_MOTION: &[(&str, &str)] = &[
    (
        "i_gain, d_gain",
        "registers the servo holds: read them (`dbot dxl read`) and give them in the model; they are \
         used, not fitted. Fitted, the D gain's drive on the error's rate is indistinguishable from \
         gear damping in the suspended excitation (the stand-in's fit put D at 0 and the damping at \
         the sum). Given, their known registers carry the stall torque's scale (Ki and Kd are per \
         unit of PWM), which is what makes the stall torque identifiable below saturation",
    ),
    (
        "no_load_speed_rad_s",
        "the torque-speed line's slope (stall / no-load speed) damps the joint exactly as the gear \
         damping does while the PWM does not saturate, which the excitation avoids: position and \
         velocity see only their sum, which the fitted damping carries (the slope is kept at the \
         model's, the no-load speed following the fitted stall torque)",
    ),
];

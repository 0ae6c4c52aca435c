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

/// The parameters fitted from motion, in this order.
pub const MOTION: &[Fitted] = &[
    Fitted {
        name: "p_gain_divisor",
        unit: "",
        lo: 32.0,
        hi: 1024.0,
        scale: 100.0,
        step: 2.0,
        get: |p| p.p_gain_divisor,
        set: |e, v| e.p_gain_divisor = Some(v),
    },
    Fitted {
        name: "stall_torque_nm",
        unit: "N m",
        lo: 0.2,
        hi: 20.0,
        scale: 1.0,
        step: 0.05,
        get: |p| p.stall_torque_nm,
        set: |e, v| e.stall_torque_nm = Some(v),
    },
    Fitted {
        name: "damping_nm_s_per_rad",
        unit: "N m s/rad",
        lo: 0.0,
        hi: 1.0,
        scale: 0.01,
        step: 0.002,
        get: |p| p.damping_nm_s_per_rad,
        set: |e, v| e.damping_nm_s_per_rad = Some(v),
    },
    Fitted {
        name: "friction_nm",
        unit: "N m",
        lo: 0.0,
        hi: 0.5,
        scale: 0.01,
        step: 0.003,
        get: |p| p.friction_nm,
        set: |e, v| e.friction_nm = Some(v),
    },
    Fitted {
        name: "armature_kg_m2",
        unit: "kg m^2",
        lo: 0.0,
        hi: 0.05,
        scale: 1e-3,
        step: 3e-4,
        get: |p| p.armature_kg_m2,
        set: |e, v| e.armature_kg_m2 = Some(v),
    },
    Fitted {
        name: "deadband_rad",
        unit: "rad",
        lo: 0.0,
        hi: 0.02,
        scale: TICK,
        step: 0.5 * TICK,
        get: |p| p.deadband_rad,
        set: |e, v| e.deadband_rad = Some(v),
    },
    Fitted {
        name: "backlash_rad",
        unit: "rad",
        lo: 0.0,
        hi: 0.02,
        scale: TICK,
        step: 0.5 * TICK,
        get: |p| p.backlash_rad,
        set: |e, v| e.backlash_rad = Some(v),
    },
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

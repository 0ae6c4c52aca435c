//! The virtual servo's heat and supply: Present Temperature (146) from the motor current and
//! Present Input Voltage (144) from the chain's total current. ROBOTIS publishes no thermal curve
//! and no supply model, so everything here is an ESTIMATE, good enough to test the firmware's
//! heat and supply watch end to end, not to predict a real servo's temperature.
//!
//! - Motor current: I = I_stall * |tau| / tau_stall, the DC motor's current proportional to its
//!   torque through the datasheet's stall point (12 V: MX-28 1.4 A at 2.5 N m, MX-64 4.1 A at
//!   6.0 N m). The electronics' standby current (about 0.1 A each) is left out: a resting servo
//!   neither heats nor loads the supply.
//! - Winding resistance: R = 12 V / I_stall (the stall current is what the winding lets through at
//!   12 V): MX-28 8.6 ohm, MX-64 2.9 ohm.
//! - Heat: one first-order thermal body, C dT/dt = I^2 R - (T - T_ambient) / R_th with time
//!   constant tau_th = R_th C, integrated exactly for a constant current over a step:
//!   T(t + dt) = T_ss + (T(t) - T_ss) exp(-dt / tau_th), T_ss = T_ambient + I^2 R R_th.
//! - Supply: V = V_supply - R_line * sum(I) over the chain (one shared supply wire).
//!
//! A servo past its Temperature Limit (31) latches the overheat error and, as the Shutdown
//! register (63) says by default, drops its torque: what the firmware's watch is there to avoid.

use crate::model::ServoModel;

/// The supply voltage the stall currents are given at (e-manual datasheet), V.
pub const DATASHEET_VOLTS: f64 = 12.0;

/// One servo's thermal body. ESTIMATE: the defaults come from no measurement; users report an
/// MX-64 stalled at 12 V and 2 A cutting out after about 20 s, which a 60 s time constant and
/// 8 K/W roughly reproduce (about 35 s from 36 to 80 degC at 11.7 W).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Thermal {
    /// Thermal resistance from the winding to the air, K/W (ESTIMATE).
    pub r_th_k_per_w: f64,
    /// Thermal time constant R_th * C, s (ESTIMATE).
    pub tau_s: f64,
    /// Air temperature, degC (the servo's power-on Present Temperature, 36, in the simulation).
    pub ambient_c: f64,
}

impl Thermal {
    /// The MX(2.0) servos' thermal body (ESTIMATE, see the type).
    pub const MX: Self = Self {
        r_th_k_per_w: 8.0,
        tau_s: 60.0,
        ambient_c: 36.0,
    };

    /// Steady temperature at a constant motor current `current_a` through `model`'s winding, degC.
    pub fn steady_c(&self, model: ServoModel, current_a: f64) -> f64 {
        self.ambient_c + heat_w(model, current_a) * self.r_th_k_per_w
    }

    /// The temperature `dt_s` seconds after `t_c` at a constant current (exact first-order step).
    pub fn step_c(&self, model: ServoModel, t_c: f64, current_a: f64, dt_s: f64) -> f64 {
        self.step_c_decayed(model, t_c, current_a, self.decay(dt_s))
    }

    /// The share of the distance to the steady temperature left after `dt_s` seconds.
    pub fn decay(&self, dt_s: f64) -> f64 {
        if self.tau_s > 0.0 {
            (-dt_s.max(0.0) / self.tau_s).exp()
        } else {
            0.0
        }
    }

    /// [`Self::step_c`] with the step's [`Self::decay`] given (a chain of servos with the same
    /// time constant computes it once per step).
    pub fn step_c_decayed(&self, model: ServoModel, t_c: f64, current_a: f64, decay: f64) -> f64 {
        let steady = self.steady_c(model, current_a);
        steady + (t_c - steady) * decay
    }
}

impl Default for Thermal {
    fn default() -> Self {
        Self::MX
    }
}

/// The chain's supply: a source and the shared wire's resistance. ESTIMATE: 12.0 V (the servos'
/// recommended supply) and 0.05 ohm (about 1 m of 18 AWG there and back, with connectors).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Supply {
    pub volts: f64,
    pub line_ohm: f64,
}

impl Supply {
    pub const DEFAULT: Self = Self {
        volts: DATASHEET_VOLTS,
        line_ohm: 0.05,
    };

    /// Voltage at the servos with `total_a` flowing through the line, V.
    pub fn at_servos(&self, total_a: f64) -> f64 {
        self.volts - self.line_ohm * total_a
    }
}

impl Default for Supply {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Winding resistance, ohm: the datasheet's 12 V over its stall current (ESTIMATE).
pub fn winding_ohm(model: ServoModel) -> f64 {
    DATASHEET_VOLTS / model.stall_current_a() as f64
}

/// Motor current at output torque `torque_nm`, A: proportional to torque through the stall point
/// (ESTIMATE).
pub fn motor_current_a(model: ServoModel, torque_nm: f64) -> f64 {
    model.stall_current_a() as f64 * torque_nm.abs() / model.stall_torque_nm() as f64
}

/// Heat dissipated in the winding at `current_a`, W.
pub fn heat_w(model: ServoModel, current_a: f64) -> f64 {
    current_a * current_a * winding_ohm(model)
}

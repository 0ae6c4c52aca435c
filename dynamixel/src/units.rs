//! Unit conversions between servo registers and SI: velocity and load/current -> torque. (Joint
//! angle <-> ticks, with the joint's zero and direction, is `protocol::Calibration`; the model's
//! constants are [`ServoModel`]'s.) The torque conversions and
//! the stiffness of the P controller are ESTIMATES: ROBOTIS publishes no current-to-torque or
//! gain-to-stiffness model, only performance graphs.

use crate::model::ServoModel;
use core::f32::consts::TAU;

// Constants of the servos themselves are the model's (`crate::model`); they are named here too
// because every conversion below uses them.
pub use crate::model::{PWM_FULL_SCALE, TICKS_PER_REV};
/// Radians per tick.
pub const RAD_PER_TICK: f32 = TAU / TICKS_PER_REV as f32;
/// Present Velocity / Velocity Limit unit: 0.229 rev/min (e-manual, MX(2.0)).
pub const VELOCITY_UNIT_RPM: f32 = 0.229;
/// Present Velocity unit in rad/s.
pub const RAD_S_PER_VELOCITY_UNIT: f32 = VELOCITY_UNIT_RPM * TAU / 60.0;
/// MX-64 Present Current unit in mA (e-manual: about 3.36 mA).
pub const CURRENT_UNIT_MA: f32 = 3.36;

/// Rounds half away from zero without `std` (saturating at the i32 range).
fn round_i32(x: f32) -> i32 {
    if x >= 0.0 {
        (x + 0.5) as i32
    } else {
        (x - 0.5) as i32
    }
}

/// Joint velocity in rad/s of a Present Velocity value (servo direction).
pub fn velocity_to_rad_s(raw: i32) -> f32 {
    raw as f32 * RAD_S_PER_VELOCITY_UNIT
}

/// Servo output torque in N m from register 126 (ESTIMATE). MX-28: Present Load is 0.1 % of
/// maximum and is itself estimated by the servo; 100 % is taken as the stall torque (2.5 N m).
/// MX-64: Present Current (3.36 mA/unit) times the stall torque/stall current ratio
/// (6.0 N m / 4.1 A = 1.46 N m/A), a linear model through the origin that ignores no-load current
/// and friction. Positive means the servo pushes toward increasing ticks.
pub fn load_to_torque_nm(model: ServoModel, raw: i16) -> f32 {
    match model {
        ServoModel::Mx28 => raw as f32 * 0.001 * model.stall_torque_nm(),
        ServoModel::Mx64 => {
            raw as f32 * CURRENT_UNIT_MA * 0.001 * model.stall_torque_nm() / model.stall_current_a()
        }
    }
}

/// The same ESTIMATE in integer mN m for the firmware (no float on the hot path).
pub fn load_to_torque_mnm(model: ServoModel, raw: i16) -> i32 {
    let raw = raw as i32;
    match model {
        // raw * 0.1 % * 2500 mN m
        ServoModel::Mx28 => raw * 5 / 2,
        // raw * 3.36 mA * 6000 mN m / 4100 mA
        ServoModel::Mx64 => raw * 20_160 / 4_100,
    }
}

/// Register 126 value the servo would report for an output torque in N m (inverse of
/// [`load_to_torque_nm`], same ESTIMATE; clamped to +-1000 for the MX-28's load).
pub fn torque_to_load(model: ServoModel, torque_nm: f32) -> i16 {
    match model {
        ServoModel::Mx28 => {
            round_i32(torque_nm / model.stall_torque_nm() * 1000.0).clamp(-1000, 1000) as i16
        }
        ServoModel::Mx64 => {
            let ma = torque_nm * model.stall_current_a() / model.stall_torque_nm() * 1000.0;
            round_i32(ma / CURRENT_UNIT_MA).clamp(i16::MIN as i32, i16::MAX as i32) as i16
        }
    }
}

/// Position-loop stiffness in N m/rad for a Position P Gain register value (ESTIMATE, see
/// [`ServoModel::stiffness_per_p_gain`]). Default P = 850 gives about 12.2 N m/rad for the MX-28
/// (the original solver used 8.4) and 29.4 N m/rad for the MX-64.
pub fn stiffness_nm_per_rad(model: ServoModel, p_gain: u16) -> f32 {
    p_gain as f32 * model.stiffness_per_p_gain()
}

/// Highest Position P Gain register value (MX(2.0) e-manual: 0 to 16383).
pub const P_GAIN_MAX: u16 = 16_383;

/// Position P Gain register value whose stiffness ([`stiffness_nm_per_rad`], same ESTIMATE) is
/// nearest `stiffness_nm_per_rad`: the inverse of that one conversion. A positive stiffness gives at
/// least 1 (never the limp servo of P = 0); 0, negative or NaN gives 0, above the register's range
/// [`P_GAIN_MAX`]. MX-28: 1 unit = 0.0144 N m/rad, so 12.23 N m/rad -> 850.
pub fn p_gain_for_stiffness(model: ServoModel, stiffness_nm_per_rad: f32) -> u16 {
    if stiffness_nm_per_rad.is_nan() || stiffness_nm_per_rad <= 0.0 {
        return 0;
    }
    let p = round_i32(stiffness_nm_per_rad / model.stiffness_per_p_gain());
    p.clamp(1, i32::from(P_GAIN_MAX)) as u16
}

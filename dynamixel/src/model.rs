//! [`ServoModel`]: the servo models of the robot and every constant that belongs to one (e-manual and
//! datasheet figures, plus the ESTIMATES this project derives from them), in one place. Adding a
//! model is adding a variant here: every `match` over it (in this crate, the step-table format, the
//! firmware, the host) is exhaustive, so the compiler lists each place that must learn the new one.

use core::f32::consts::TAU;

/// Encoder ticks per revolution of every MX(2.0) model (0.088 deg per tick; per model:
/// [`ServoModel::ticks_per_rev`]).
pub const TICKS_PER_REV: i32 = 4096;
/// PWM that equals 100 % duty (PWM Limit default, e-manual).
pub const PWM_FULL_SCALE: f32 = 885.0;
/// Divisor of the Position P Gain register: Kp = P / 128 in PWM per tick of error (e-manual;
/// ESTIMATE for the servo's real behaviour: BAM measured 256 on X-series servos).
pub const P_GAIN_DIVISOR: f32 = 128.0;
/// Divisor of the Position I Gain register: Ki = I / 65536 (e-manual).
pub const I_GAIN_DIVISOR: f32 = 65_536.0;
/// Divisor of the Position D Gain register: Kd = D / 16 (e-manual).
pub const D_GAIN_DIVISOR: f32 = 16.0;
/// Position I Gain and D Gain registers at power-on (e-manual defaults; P is 850).
pub const I_GAIN_DEFAULT: u16 = 0;
pub const D_GAIN_DEFAULT: u16 = 0;

/// A Dynamixel servo model (protocol 2.0 firmware).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ServoModel {
    /// Dynamixel MX-28(2.0), 2.5 N m stall at 12 V.
    Mx28,
    /// Dynamixel MX-64(2.0), 6.0 N m stall at 12 V.
    Mx64,
}

impl ServoModel {
    /// Every model, in step-table code order.
    pub const ALL: [ServoModel; 2] = [ServoModel::Mx28, ServoModel::Mx64];

    /// Model Number register value (MX-28(2.0) = 30, MX-64(2.0) = 311, e-manual).
    pub const fn number(self) -> u16 {
        match self {
            Self::Mx28 => 30,
            Self::Mx64 => 311,
        }
    }

    /// The model of a Model Number register value.
    pub fn from_number(n: u16) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.number() == n)
    }

    /// The byte that names the model in a step table (`protocol::gait`); never reused.
    pub const fn table_code(self) -> u8 {
        match self {
            Self::Mx28 => 0,
            Self::Mx64 => 1,
        }
    }

    /// The model of a step-table code.
    pub fn from_table_code(code: u8) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.table_code() == code)
    }

    /// The model's name in a model file's `actuation` field (`"mx28"`).
    pub const fn key(self) -> &'static str {
        match self {
            Self::Mx28 => "mx28",
            Self::Mx64 => "mx64",
        }
    }

    /// The model of a model file's `actuation` name ([`ServoModel::key`]).
    pub fn from_key(key: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.key() == key)
    }

    /// The e-manual's name.
    pub const fn name(self) -> &'static str {
        match self {
            Self::Mx28 => "MX-28(2.0)",
            Self::Mx64 => "MX-64(2.0)",
        }
    }

    /// Encoder ticks per output revolution (0.088 deg per tick on both, e-manual).
    pub const fn ticks_per_rev(self) -> i32 {
        match self {
            Self::Mx28 | Self::Mx64 => TICKS_PER_REV,
        }
    }

    /// Stall torque at 12 V in N m (e-manual datasheet).
    pub const fn stall_torque_nm(self) -> f32 {
        match self {
            Self::Mx28 => 2.5,
            Self::Mx64 => 6.0,
        }
    }

    /// Stall current at 12 V in A (e-manual datasheet).
    pub const fn stall_current_a(self) -> f32 {
        match self {
            Self::Mx28 => 1.4,
            Self::Mx64 => 4.1,
        }
    }

    /// No-load speed at 12 V in rev/min (e-manual: MX-28 55, MX-64 63).
    pub const fn no_load_speed_rpm(self) -> f32 {
        match self {
            Self::Mx28 => 55.0,
            Self::Mx64 => 63.0,
        }
    }

    /// No-load speed at 12 V in rad/s.
    pub fn no_load_speed_rad_s(self) -> f32 {
        self.no_load_speed_rpm() * TAU / 60.0
    }

    /// Whether register 126 is Present Current (MX-64) rather than Present Load (MX-28).
    pub const fn reports_current(self) -> bool {
        match self {
            Self::Mx28 => false,
            Self::Mx64 => true,
        }
    }

    /// Reflected rotor inertia at the output shaft, kg m^2 (ESTIMATE: a coreless rotor of about
    /// 0.9 g cm^2 (MX-28) or 2 g cm^2 (MX-64), times the gear ratio squared, 193 and 200): the
    /// armature of the joint in the MuJoCo model.
    pub fn armature_kg_m2(self) -> f64 {
        let (rotor, gear) = match self {
            Self::Mx28 => (0.9e-7, 193.0),
            Self::Mx64 => (2.0e-7, 200.0),
        };
        rotor * gear * gear
    }

    /// Position-loop stiffness in N m/rad per unit of Position P Gain (ESTIMATE).
    ///
    /// The e-manual gives Kp = P / 128 acting on the position error in ticks and producing PWM
    /// (885 = 100 %). Assuming torque proportional to PWM up to the stall torque (no back-EMF, no
    /// friction, i.e. a servo holding still), k = (P/128) / 885 * stall torque * ticks per rad.
    pub fn stiffness_per_p_gain(self) -> f32 {
        (1.0 / P_GAIN_DIVISOR) / PWM_FULL_SCALE
            * self.stall_torque_nm()
            * self.ticks_per_rev() as f32
            / TAU
    }
}

impl core::fmt::Display for ServoModel {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_and_numbers_are_distinct_and_round_trip() {
        for m in ServoModel::ALL {
            assert_eq!(ServoModel::from_number(m.number()), Some(m));
            assert_eq!(ServoModel::from_table_code(m.table_code()), Some(m));
        }
        assert_eq!(ServoModel::from_number(29), None);
        assert_eq!(ServoModel::from_table_code(2), None);
        for m in ServoModel::ALL {
            assert_eq!(ServoModel::from_key(m.key()), Some(m));
        }
        assert_eq!(ServoModel::from_key("mx106"), None);
    }

    #[test]
    fn datasheet_figures() {
        // MX-28: 55 rev/min = 5.76 rad/s; MX-64: 63 rev/min = 6.60 rad/s.
        assert!((ServoModel::Mx28.no_load_speed_rad_s() - 5.7596).abs() < 1e-3);
        assert!((ServoModel::Mx64.no_load_speed_rad_s() - 6.5973).abs() < 1e-3);
        // (1/128)/885 x 2.5 N m x 4096 / 2 pi = 0.014 386 N m/rad per P unit.
        assert!((ServoModel::Mx28.stiffness_per_p_gain() - 0.014_386).abs() < 1e-5);
    }
}

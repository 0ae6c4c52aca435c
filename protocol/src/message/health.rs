//! Heat and supply of the servos (appended: protocol version 8): what the board reads of each
//! servo's Present Temperature (146) and Present Input Voltage (144), the limits at which it warns
//! and at which it stops a walk at the end of its step, and the alarm naming the servo.
//!
//! The default limits keep a margin below the servos' own (MX(2.0) e-manual: Temperature Limit
//! 80 degC with an overheat shutdown, Min / Max Voltage Limit 9.5 / 16.0 V; recommended supply
//! 10 to 14.8 V, 12 V nominal). They are choices, not published values, hence settable:
//! - stop at 75 degC: the walk ends at the end of its step, up to one step later (2.5 s at the
//!   default plan): 5 degC leaves room for that step's heating (an MX-64 stalled at 2 A was
//!   reported to rise about 2 degC/s) before the servo's own shutdown drops the robot;
//!   warn at 70 degC, as some labs set their limit;
//! - stop below 10.0 V, the bottom of the recommended range, 0.5 V above the 9.5 V where the servo
//!   flags an input voltage error (which by default does not stop it: nothing else would); warn
//!   below 10.5 V;
//! - stop above 15.5 V, 0.5 V below the 16.0 V limit; warn above 14.8 V, the top of the
//!   recommended range.

use core::fmt;

/// The servos' own overheat limit (Temperature Limit, register 31, factory default), degC: the
/// stop limit must lie below it.
pub const SERVO_TEMPERATURE_LIMIT_C: u8 = 80;
/// The servos' own input voltage limits (registers 34 / 32, factory defaults), 0.1 V.
pub const SERVO_MIN_VOLTAGE_DV: u16 = 95;
pub const SERVO_MAX_VOLTAGE_DV: u16 = 160;

/// One servo's last heat and supply reading. `temperature_c` 0 and `voltage_dv` 0: not read yet.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ServoHealth {
    /// Present Temperature, degC.
    pub temperature_c: u8,
    /// Present Input Voltage, 0.1 V.
    pub voltage_dv: u16,
}

impl ServoHealth {
    /// Whether the servo has been read since the joint map changed.
    pub const fn is_read(&self) -> bool {
        self.voltage_dv != 0 || self.temperature_c != 0
    }
}

/// Where the board warns and where it stops a walk (see the module for the defaults' reasons).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HealthLimits {
    /// Warn at or above this temperature, degC.
    pub warn_temperature_c: u8,
    /// Stop the walk at the end of its step at or above this temperature, degC.
    pub stop_temperature_c: u8,
    /// Warn at or below this input voltage, 0.1 V.
    pub warn_low_dv: u16,
    /// Stop at or below this input voltage, 0.1 V.
    pub stop_low_dv: u16,
    /// Warn at or above this input voltage, 0.1 V.
    pub warn_high_dv: u16,
    /// Stop at or above this input voltage, 0.1 V.
    pub stop_high_dv: u16,
}

impl HealthLimits {
    pub const DEFAULT: Self = Self {
        warn_temperature_c: 70,
        stop_temperature_c: 75,
        warn_low_dv: 105,
        stop_low_dv: 100,
        warn_high_dv: 148,
        stop_high_dv: 155,
    };

    /// Checks the order the limits must keep: warn before stop, stop inside the servos' own
    /// limits. The error names the first limit out of order.
    pub fn check(&self) -> Result<(), HealthLimitError> {
        use HealthLimitError as E;
        if self.stop_temperature_c >= SERVO_TEMPERATURE_LIMIT_C {
            return Err(E::StopTemperature(self.stop_temperature_c));
        }
        if self.warn_temperature_c > self.stop_temperature_c {
            return Err(E::WarnTemperature(self.warn_temperature_c));
        }
        if self.stop_low_dv <= SERVO_MIN_VOLTAGE_DV {
            return Err(E::StopLow(self.stop_low_dv));
        }
        if self.warn_low_dv < self.stop_low_dv {
            return Err(E::WarnLow(self.warn_low_dv));
        }
        if self.stop_high_dv >= SERVO_MAX_VOLTAGE_DV {
            return Err(E::StopHigh(self.stop_high_dv));
        }
        if self.warn_high_dv > self.stop_high_dv || self.warn_high_dv <= self.warn_low_dv {
            return Err(E::WarnHigh(self.warn_high_dv));
        }
        Ok(())
    }

    /// What `reading` means against these limits: the worst of temperature and voltage (a stop
    /// before a warning; temperature first when both are at the same level).
    pub fn classify(&self, reading: ServoHealth) -> Option<(HealthKind, HealthLevel, u16)> {
        if !reading.is_read() {
            return None;
        }
        let t = reading.temperature_c;
        let v = reading.voltage_dv;
        let checks = [
            (
                HealthKind::Hot,
                t >= self.stop_temperature_c,
                t >= self.warn_temperature_c,
                u16::from(t),
            ),
            (
                HealthKind::LowVoltage,
                v <= self.stop_low_dv,
                v <= self.warn_low_dv,
                v,
            ),
            (
                HealthKind::HighVoltage,
                v >= self.stop_high_dv,
                v >= self.warn_high_dv,
                v,
            ),
        ];
        let stop = checks
            .iter()
            .find(|c| c.1)
            .map(|c| (c.0, HealthLevel::Stop, c.3));
        stop.or_else(|| {
            checks
                .iter()
                .find(|c| c.2)
                .map(|c| (c.0, HealthLevel::Warn, c.3))
        })
    }

    /// The limit of `kind` at `level`, in the reading's unit (degC or 0.1 V).
    pub fn limit(&self, kind: HealthKind, level: HealthLevel) -> u16 {
        match (kind, level) {
            (HealthKind::Hot, HealthLevel::Warn) => u16::from(self.warn_temperature_c),
            (HealthKind::Hot, HealthLevel::Stop) => u16::from(self.stop_temperature_c),
            (HealthKind::LowVoltage, HealthLevel::Warn) => self.warn_low_dv,
            (HealthKind::LowVoltage, HealthLevel::Stop) => self.stop_low_dv,
            (HealthKind::HighVoltage, HealthLevel::Warn) => self.warn_high_dv,
            (HealthKind::HighVoltage, HealthLevel::Stop) => self.stop_high_dv,
        }
    }
}

impl Default for HealthLimits {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// A limit out of order (the value given); see [`HealthLimits::check`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HealthLimitError {
    StopTemperature(u8),
    WarnTemperature(u8),
    StopLow(u16),
    WarnLow(u16),
    StopHigh(u16),
    WarnHigh(u16),
}

impl HealthLimitError {
    /// The value refused, for [`super::ProtocolError::InvalidSetting`].
    pub fn value(&self) -> i32 {
        match *self {
            Self::StopTemperature(v) | Self::WarnTemperature(v) => i32::from(v),
            Self::StopLow(v) | Self::WarnLow(v) | Self::StopHigh(v) | Self::WarnHigh(v) => {
                i32::from(v)
            }
        }
    }
}

impl fmt::Display for HealthLimitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let dv = |v: u16| (v / 10, v % 10);
        match *self {
            Self::StopTemperature(v) => write!(
                f,
                "stop temperature {v} degC must be below the servos' own limit {SERVO_TEMPERATURE_LIMIT_C} degC"
            ),
            Self::WarnTemperature(v) => {
                write!(
                    f,
                    "warn temperature {v} degC must not be above the stop temperature"
                )
            }
            Self::StopLow(v) => {
                let (a, b) = dv(v);
                write!(
                    f,
                    "stop voltage low {a}.{b} V must be above the servos' own 9.5 V"
                )
            }
            Self::WarnLow(v) => {
                let (a, b) = dv(v);
                write!(
                    f,
                    "warn voltage low {a}.{b} V must not be below the stop voltage low"
                )
            }
            Self::StopHigh(v) => {
                let (a, b) = dv(v);
                write!(
                    f,
                    "stop voltage high {a}.{b} V must be below the servos' own 16.0 V"
                )
            }
            Self::WarnHigh(v) => {
                let (a, b) = dv(v);
                write!(
                    f,
                    "warn voltage high {a}.{b} V must lie above warn voltage low and not above stop voltage high"
                )
            }
        }
    }
}

/// What a reading is out of.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum HealthKind {
    /// Present Temperature at or above a temperature limit.
    Hot,
    /// Present Input Voltage at or below a low limit.
    LowVoltage,
    /// Present Input Voltage at or above a high limit.
    HighVoltage,
}

/// How far out: a warning, or the walk stops at the end of its step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum HealthLevel {
    Warn,
    Stop,
}

/// A servo out of a limit: which (joint index and bus ID), what, its reading and the limit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HealthAlarm {
    pub joint: u8,
    pub id: u8,
    pub kind: HealthKind,
    pub level: HealthLevel,
    /// The reading, degC ([`HealthKind::Hot`]) or 0.1 V.
    pub value: u16,
    /// The limit it reached, same unit.
    pub limit: u16,
}

impl fmt::Display for HealthAlarm {
    /// `servo ID 5 (joint 4): 76 degC, at or above the stop limit 75 degC` (the host puts the
    /// joint's name in front).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let level = match self.level {
            HealthLevel::Warn => "warning",
            HealthLevel::Stop => "stop",
        };
        write!(f, "servo ID {} (joint {}): ", self.id, self.joint)?;
        match self.kind {
            HealthKind::Hot => write!(
                f,
                "{} degC, at or above the {level} limit {} degC",
                self.value, self.limit
            ),
            HealthKind::LowVoltage | HealthKind::HighVoltage => {
                let side = if self.kind == HealthKind::LowVoltage {
                    "below"
                } else {
                    "above"
                };
                write!(
                    f,
                    "supply {}.{} V, at or {side} the {level} limit {}.{} V",
                    self.value / 10,
                    self.value % 10,
                    self.limit / 10,
                    self.limit % 10
                )
            }
        }
    }
}

//! The servos' heat and supply as the host says them: the limits from degC and volts (checked by
//! the one rule, `protocol::HealthLimits::check`, so `dbot set` and Python's
//! `Board.set_health_limits` refuse in the same words), and an alarm naming the servo's joint.

use protocol::{HealthAlarm, HealthLevel, HealthLimits};

/// Limits in the user's units; `None` keeps the value of `base`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct HealthLimitArgs {
    pub warn_temperature_c: Option<f64>,
    pub stop_temperature_c: Option<f64>,
    pub warn_low_v: Option<f64>,
    pub stop_low_v: Option<f64>,
    pub warn_high_v: Option<f64>,
    pub stop_high_v: Option<f64>,
}

impl HealthLimitArgs {
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }
}

/// A limit the board cannot take.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HealthLimitsError {
    #[error("{name} {value}: not a number the board holds ({range})")]
    Unit {
        name: &'static str,
        value: f64,
        range: &'static str,
    },
    #[error("health limits: {0}")]
    Order(String),
}

/// `base` with the given limits replaced, checked.
pub fn health_limits(
    base: HealthLimits,
    args: &HealthLimitArgs,
) -> Result<HealthLimits, HealthLimitsError> {
    let deg = |name, v: Option<f64>, old: u8| match v {
        None => Ok(old),
        Some(x) if x.is_finite() && (0.0..=255.0).contains(&x) && x.fract() == 0.0 => Ok(x as u8),
        Some(x) => Err(HealthLimitsError::Unit {
            name,
            value: x,
            range: "whole degC, 0 to 255",
        }),
    };
    let volts = |name, v: Option<f64>, old: u16| match v {
        None => Ok(old),
        Some(x) if x.is_finite() && (0.0..=6553.5).contains(&x) => Ok((x * 10.0).round() as u16),
        Some(x) => Err(HealthLimitsError::Unit {
            name,
            value: x,
            range: "volts in 0.1 V steps",
        }),
    };
    let l = HealthLimits {
        warn_temperature_c: deg(
            "warn temperature",
            args.warn_temperature_c,
            base.warn_temperature_c,
        )?,
        stop_temperature_c: deg(
            "stop temperature",
            args.stop_temperature_c,
            base.stop_temperature_c,
        )?,
        warn_low_dv: volts("warn voltage low", args.warn_low_v, base.warn_low_dv)?,
        stop_low_dv: volts("stop voltage low", args.stop_low_v, base.stop_low_dv)?,
        warn_high_dv: volts("warn voltage high", args.warn_high_v, base.warn_high_dv)?,
        stop_high_dv: volts("stop voltage high", args.stop_high_v, base.stop_high_dv)?,
    };
    l.check()
        .map_err(|e| HealthLimitsError::Order(e.to_string()))?;
    Ok(l)
}

/// The limits in one line: `warn 70 degC, stop 75 degC; supply warn below 10.5 V / above 14.8 V,
/// stop below 10.0 V / above 15.5 V`.
pub fn limits_line(l: &HealthLimits) -> String {
    let v = |dv: u16| f64::from(dv) / 10.0;
    format!(
        "temperature warn {} degC, stop {} degC; supply warn at {:.1} V / {:.1} V, stop at {:.1} V / {:.1} V",
        l.warn_temperature_c,
        l.stop_temperature_c,
        v(l.warn_low_dv),
        v(l.warn_high_dv),
        v(l.stop_low_dv),
        v(l.stop_high_dv)
    )
}

/// The alarm naming the servo's joint: `joint LF_CTr, servo ID 3 (joint 2): 76 degC, at or
/// above the stop limit 75 degC; the walk stopped at the end of its step`. `names` in joint-map
/// order (`record::joint_names_by_ids`); a joint without a name is `J<n>`.
pub fn alarm_line(a: &HealthAlarm, names: &[String]) -> String {
    let name = names
        .get(usize::from(a.joint))
        .cloned()
        .unwrap_or_else(|| format!("J{}", a.joint));
    let tail = match a.level {
        HealthLevel::Warn => "",
        HealthLevel::Stop => "; the walk stopped at the end of its step",
    };
    format!("joint {name}, {a}{tail}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use protocol::HealthKind;

    #[test]
    fn limits_in_volts_and_degc_become_the_boards_units_or_are_refused_in_words() {
        let args = HealthLimitArgs {
            stop_temperature_c: Some(72.0),
            warn_low_v: Some(10.8),
            ..Default::default()
        };
        let l = health_limits(HealthLimits::DEFAULT, &args).unwrap();
        assert_eq!((l.stop_temperature_c, l.warn_low_dv), (72, 108));
        assert_eq!(l.warn_temperature_c, 70);
        let over = HealthLimitArgs {
            stop_temperature_c: Some(85.0),
            ..Default::default()
        };
        assert_eq!(
            health_limits(HealthLimits::DEFAULT, &over)
                .unwrap_err()
                .to_string(),
            "health limits: stop temperature 85 degC must be below the servos' own limit 80 degC"
        );
        let half = HealthLimitArgs {
            warn_temperature_c: Some(70.5),
            ..Default::default()
        };
        assert!(health_limits(HealthLimits::DEFAULT, &half).is_err());
    }

    #[test]
    fn an_alarm_names_the_joint_and_the_servo() {
        let a = HealthAlarm {
            joint: 1,
            id: 3,
            kind: HealthKind::LowVoltage,
            level: HealthLevel::Stop,
            value: 99,
            limit: 100,
        };
        let names = ["LF_ThC1".to_owned(), "LF_CTr".to_owned()];
        assert_eq!(
            alarm_line(&a, &names),
            "joint LF_CTr, servo ID 3 (joint 1): supply 9.9 V, at or below the stop limit 10.0 V; \
             the walk stopped at the end of its step"
        );
    }
}

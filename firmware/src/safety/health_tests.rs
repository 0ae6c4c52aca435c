//! The heat and supply watch against hand-worked cases at the default limits (warn 70 degC, stop
//! 75 degC; low 10.5 / 10.0 V; high 14.8 / 15.5 V).

use protocol::{HealthKind, HealthLevel, HealthLimits, ServoHealth, feedback_flags};

use super::health::HealthWatch;

fn reading(temperature_c: u8, voltage_dv: u16) -> ServoHealth {
    ServoHealth {
        temperature_c,
        voltage_dv,
    }
}

#[test]
fn each_limit_is_reached_at_its_value_not_before() {
    let mut w = HealthWatch::<4>::new(HealthLimits::DEFAULT);
    // (temperature, voltage) -> (kind, level, value, limit) or none.
    let cases = [
        (69, 120, None),
        (70, 120, Some((HealthKind::Hot, HealthLevel::Warn, 70, 70))),
        (74, 120, Some((HealthKind::Hot, HealthLevel::Warn, 74, 70))),
        (75, 120, Some((HealthKind::Hot, HealthLevel::Stop, 75, 75))),
        (40, 106, None),
        (
            40,
            105,
            Some((HealthKind::LowVoltage, HealthLevel::Warn, 105, 105)),
        ),
        (
            40,
            101,
            Some((HealthKind::LowVoltage, HealthLevel::Warn, 101, 105)),
        ),
        (
            40,
            100,
            Some((HealthKind::LowVoltage, HealthLevel::Stop, 100, 100)),
        ),
        (40, 147, None),
        (
            40,
            148,
            Some((HealthKind::HighVoltage, HealthLevel::Warn, 148, 148)),
        ),
        (
            40,
            155,
            Some((HealthKind::HighVoltage, HealthLevel::Stop, 155, 155)),
        ),
        // A stop outranks a warning whichever it is: warm (70) but the supply at 10.0 V.
        (
            70,
            100,
            Some((HealthKind::LowVoltage, HealthLevel::Stop, 100, 100)),
        ),
        // Both at stop: temperature is named first.
        (80, 90, Some((HealthKind::Hot, HealthLevel::Stop, 80, 75))),
    ];
    for (t, v, want) in cases {
        let got = w
            .record(2, 7, reading(t, v))
            .map(|a| (a.kind, a.level, a.value, a.limit));
        assert_eq!(got, want, "{t} degC, {v} dV");
        if let Some(a) = w.alarm(2, 7) {
            assert_eq!((a.joint, a.id), (2, 7));
        }
    }
}

#[test]
fn an_unread_servo_raises_nothing_and_the_worst_servo_is_named() {
    let mut w = HealthWatch::<4>::new(HealthLimits::DEFAULT);
    // Not read yet: 0 degC, 0 V is no reading, not an undervoltage.
    assert_eq!(w.alarm(0, 1), None);
    w.record(0, 11, reading(71, 120));
    w.record(1, 12, reading(40, 120));
    w.record(3, 14, reading(76, 120));
    let worst = w.worst([11, 12, 13, 14].into_iter()).unwrap();
    assert_eq!(
        (worst.joint, worst.id, worst.level),
        (3, 14, HealthLevel::Stop)
    );
    assert_eq!(w.flags(0), feedback_flags::HEALTH_WARN);
    assert_eq!(w.flags(1), 0);
    assert_eq!(w.flags(3), feedback_flags::HEALTH_STOP);
    // Cooled below the warning: joint 3 no longer counts, joint 0's warning is the worst.
    w.record(3, 14, reading(69, 120));
    let worst = w.worst([11, 12, 13, 14].into_iter()).unwrap();
    assert_eq!(
        (worst.joint, worst.id, worst.level),
        (0, 11, HealthLevel::Warn)
    );
    w.reset();
    assert_eq!(w.worst([11, 12, 13, 14].into_iter()), None);
}

#[test]
fn servos_are_read_in_turn() {
    let mut w = HealthWatch::<32>::new(HealthLimits::DEFAULT);
    let order: Vec<usize> = (0..7).filter_map(|_| w.next_joint(3)).collect();
    assert_eq!(order, [0, 1, 2, 0, 1, 2, 0]);
    assert_eq!(w.next_joint(0), None);
}

#[test]
fn limits_out_of_order_are_refused_naming_the_limit() {
    let ok = HealthLimits::DEFAULT;
    assert_eq!(ok.check(), Ok(()));
    let at_servo_limit = HealthLimits {
        stop_temperature_c: 80,
        ..ok
    };
    assert_eq!(
        at_servo_limit.check().unwrap_err().to_string(),
        "stop temperature 80 degC must be below the servos' own limit 80 degC"
    );
    let warn_after_stop = HealthLimits {
        warn_temperature_c: 76,
        ..ok
    };
    assert!(warn_after_stop.check().is_err());
    let low_at_servo = HealthLimits {
        stop_low_dv: 95,
        ..ok
    };
    assert_eq!(
        low_at_servo.check().unwrap_err().to_string(),
        "stop voltage low 9.5 V must be above the servos' own 9.5 V"
    );
}

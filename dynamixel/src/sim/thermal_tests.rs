//! The virtual servos' heat and supply against hand-worked numbers: the first-order response of
//! the thermal body at the datasheet's stall current, the overheat shutdown at the Temperature
//! Limit, and the line drop of the supply.

use super::thermal::{Supply, Thermal};
use super::{Faults, VirtualChain};
use crate::control_table as ct;
use crate::model::ServoModel;

/// A chain of one MX-28 (ID 1) and one MX-64 (ID 2); servo 1 stalled at full duty (jammed gear,
/// goal far away, torque on): it delivers its stall torque, 2.5 N m, at the stall current 1.4 A.
fn stalled_mx28(supply: Supply) -> VirtualChain {
    let mut c =
        VirtualChain::new(&[(1, ServoModel::Mx28), (2, ServoModel::Mx64)], 1_000_000).unwrap();
    c.supply = supply;
    let s = c.servo_mut(1).unwrap();
    s.faults = Faults::JAMMED;
    s.put(ct::TORQUE_ENABLE, 1);
    s.put(ct::GOAL_POSITION, 4000);
    c
}

#[test]
fn a_stalled_servo_heats_along_the_first_order_response() {
    let mut c = stalled_mx28(Supply::DEFAULT);
    // Hand-worked: winding R = 12 V / 1.4 A; at 1.4 A it dissipates 1.4^2 * 12 / 1.4 = 16.8 W;
    // 8 K/W above 36 degC: steady at 36 + 134.4 = 170.4 degC (never reached: the limit cuts it),
    // T(t) = 36 + 134.4 (1 - exp(-t / 60 s)).
    let closed = |t: f64| 36.0 + 16.8 * 8.0 * (1.0 - (-t / 60.0).exp());
    let dt = 0.01;
    let mut t = 0.0;
    for check in [1.0, 5.0, 10.0, 20.0] {
        while t < check - 1e-9 {
            c.step(dt);
            t += dt;
        }
        let s = c.servo(1).unwrap();
        assert!(
            (s.temperature_c() - closed(t)).abs() < 1e-6,
            "at {t:.2} s: {} degC, closed form {} degC",
            s.temperature_c(),
            closed(t)
        );
        assert_eq!(s.get(ct::PRESENT_TEMPERATURE), closed(t).round() as u32);
        // The resting MX-64 draws nothing and stays at the air's 36 degC.
        assert_eq!(c.servo(2).unwrap().get(ct::PRESENT_TEMPERATURE), 36);
    }
    // 20 s: 36 + 134.4 * (1 - exp(-1/3)) = 74.1 degC, below the 80 degC limit: still driving.
    assert!(c.servo(1).unwrap().torque_enabled());
    assert_eq!(c.servo(1).unwrap().hardware_error(), 0);
}

#[test]
fn past_the_temperature_limit_the_servo_latches_overheating_and_drops_torque() {
    let mut c = stalled_mx28(Supply::DEFAULT);
    // 80.5 degC (the register reads 81 > 80) is reached at t = -60 ln(1 - 44.5 / 134.4) = 24.127 s: the
    // 2413th step of 10 ms is the first past it.
    let mut steps = 0;
    while c.servo(1).unwrap().hardware_error() == 0 {
        assert!(c.servo(1).unwrap().torque_enabled(), "at step {steps}");
        c.step(0.01);
        steps += 1;
        assert!(steps < 10_000, "never overheated");
    }
    assert_eq!(steps, 2413, "latched at {} s", steps as f64 * 0.01);
    let s = c.servo(1).unwrap();
    assert_eq!(s.get(ct::PRESENT_TEMPERATURE), 81);
    assert_eq!(s.hardware_error(), ct::hardware_error::OVERHEATING);
    assert!(!s.torque_enabled());
    // Torque off: no current, the servo cools towards the air with the same time constant.
    let hot = s.temperature_c();
    for _ in 0..6000 {
        c.step(0.01);
    }
    let cooled = c.servo(1).unwrap().temperature_c();
    let want = 36.0 + (hot - 36.0) * (-1.0f64).exp();
    assert!((cooled - want).abs() < 1e-6, "{cooled} vs {want}");
}

#[test]
fn the_supply_sags_by_the_line_drop_of_the_total_current() {
    // 0.5 ohm line: the stalled MX-28's 1.4 A drops 0.7 V; every servo on the chain sees 11.3 V.
    let mut c = stalled_mx28(Supply {
        volts: 12.0,
        line_ohm: 0.5,
    });
    assert_eq!(c.servo(1).unwrap().get(ct::PRESENT_INPUT_VOLTAGE), 120);
    c.step(0.01);
    for id in [1, 2] {
        assert_eq!(c.servo(id).unwrap().get(ct::PRESENT_INPUT_VOLTAGE), 113);
    }
    // A high thermal resistance is the knob that makes one servo heat fast: 100x the default
    // rises 100x as far in the first instant (the same time constant).
    let fast = Thermal {
        r_th_k_per_w: 800.0,
        ..Thermal::MX
    };
    let mut slow = stalled_mx28(Supply::DEFAULT);
    let mut quick = stalled_mx28(Supply::DEFAULT);
    quick.set_thermal(1, fast).unwrap();
    slow.step(0.1);
    quick.step(0.1);
    let rise = |c: &VirtualChain| c.servo(1).unwrap().temperature_c() - 36.0;
    assert!((rise(&quick) / rise(&slow) - 100.0).abs() < 1e-9);
}

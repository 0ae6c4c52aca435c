//! Heat and supply on the simulated wire: the bus loop reads one servo's Present Input Voltage and
//! Present Temperature per cycle in the cycle's slack without costing the cycle rate, and a servo
//! that heats (the virtual chain's thermal knob) makes the board warn and then stop the walk at
//! the end of its step, naming the servo, before the servo's own 80 degC shutdown.

use dynamixel::sim::Thermal;
use firmware::safety::State;
use firmware::testkit::SyntheticGait;
use firmware::testkit::rig::{ask, telemetry, walking};
use protocol::{HealthKind, HealthLevel, Request, Response, feedback_flags};

/// Runs `n` cycles; (start of the last cycle, health reads, overruns) after them.
fn run(board: &mut firmware::testkit::rig::SimBoard, wire: &dynamixel::sim::SimWire, n: usize) {
    for _ in 0..n {
        wire.block_on(board.run_cycle());
        board.drain_telemetry(|_| {});
    }
}

#[test]
fn heat_and_supply_reads_cost_the_cycle_rate_nothing() {
    let gait = SyntheticGait::new(100, 1.0).build();
    let (mut board, wire, _) = walking(1_000_000, 100, &gait);
    let before = board.timing();
    run(&mut board, &wire, 440);
    let after = board.timing();
    // Every cycle read one servo, and every start stayed on the 10 ms grid: 440 cycles span
    // exactly 4.4 s and none was skipped.
    assert_eq!(after.health_reads - before.health_reads, 440);
    assert_eq!(after.overruns, before.overruns);
    assert_eq!(after.last_start_us - before.last_start_us, 440 * 10_000);
    assert!(after.max_busy_us < 10_000, "{after:?}");
    // 20 rounds of the 22 servos: each has been read; a resting chain on 12.0 V at 36 degC
    // (the virtual servos' power-on values; the walk's small currents move neither by 1 unit).
    let c = board.controller.borrow();
    assert_eq!(c.health_readings().len(), 22);
    for (j, r) in c.health_readings().iter().enumerate() {
        assert!((118..=120).contains(&r.voltage_dv), "joint {j}: {r:?}");
        assert!((36..=37).contains(&r.temperature_c), "joint {j}: {r:?}");
    }
    assert_eq!(c.health_warning(), None);
}

#[test]
fn without_room_before_the_next_start_no_servo_is_read_and_no_start_is_missed() {
    // 150 Hz at 1 Mbit/s: a 22-servo cycle leaves less than a read's budget before the next start.
    let gait = SyntheticGait::new(100, 1.0).build();
    let (mut board, wire, _) = walking(1_000_000, 150, &gait);
    let before = board.timing();
    run(&mut board, &wire, 300);
    let after = board.timing();
    let period = 1_000_000 / 150;
    let budget = firmware::bus_loop::health_read_budget_us(board.bus.config());
    assert!(
        u64::from(after.max_busy_us) + budget > period,
        "the test needs a cycle without room: busy {} us + read {budget} us <= {period} us",
        after.max_busy_us
    );
    assert_eq!(after.overruns, before.overruns);
    assert!(after.health_reads - before.health_reads < 300);
}

#[test]
fn a_heating_servo_warns_then_stops_the_walk_at_the_end_of_its_step_naming_it() {
    let gait = SyntheticGait::new(100, 1.0).build();
    let (mut board, wire, mut client) = walking(1_000_000, 100, &gait);
    // Servo ID 5 (joint 4) carries 1 N m and has 10x the default thermal resistance: the knob
    // that makes it heat in seconds, not minutes (ESTIMATE either way). Hand-worked:
    // I = 1.4 A * 1 / 2.5 = 0.56 A, P = 0.56^2 * 12 / 1.4 = 2.69 W, steady at 36 + 2.69 * 80 =
    // 251 degC; 70 degC after -60 ln(1 - 34 / 215) = 10.3 s, 75 after 12.0 s, rising 2.9 K/s
    // there: the 1 s step and a round of reads (0.22 s) end long before 80 degC.
    wire.with_chain(|c| {
        c.set_external_torque(5, 1.0).unwrap();
        c.set_thermal(
            5,
            Thermal {
                r_th_k_per_w: 80.0,
                tau_s: 60.0,
                ..Thermal::MX
            },
        )
        .unwrap();
    });
    let mut warned_at = None;
    let mut stop_step = None;
    let mut flags_seen = 0u8;
    for k in 0..2500 {
        wire.block_on(board.run_cycle());
        for t in telemetry(&mut board) {
            flags_seen |= t.joints[4].flags;
            assert_eq!(t.health.len(), 22);
        }
        let c = board.controller.borrow();
        if warned_at.is_none() && c.health_warning().is_some() {
            warned_at = Some(k);
        }
        if stop_step.is_none() && c.state() == State::Stopping {
            stop_step = c.playback().map(|p| p.0);
        }
        if c.state() == State::Standing {
            break;
        }
    }
    let warned_at = warned_at.expect("never warned");
    // Present Temperature reads 70 from 69.5 degC on (rounded): at -60 ln(1 - 33.5 / 215) =
    // 10.16 s into the heating; the warning comes within a round of reads (0.22 s) of it.
    assert!(
        (1016..=1038).contains(&warned_at),
        "warned at cycle {warned_at}"
    );
    assert_eq!(
        flags_seen & feedback_flags::HEALTH_WARN,
        feedback_flags::HEALTH_WARN
    );
    assert!(stop_step.is_some(), "never stopped");
    let Response::Status(s) = ask(&mut board, &mut client, Request::GetStatus) else {
        panic!("no status");
    };
    // Standing after the step the stop reading fell in: that step completed, the table's
    // slice 0 is where it stands (the end of a step).
    assert_eq!(s.state, protocol::RunState::Standing, "{:?}", s.fault);
    let stop = s.health_stop.expect("the stop names the servo");
    assert_eq!((stop.joint, stop.id), (4, 5));
    assert_eq!(
        (stop.kind, stop.level, stop.limit),
        (HealthKind::Hot, HealthLevel::Stop, 75)
    );
    assert!(stop.value >= 75);
    // Before the servo's own limit: no overheat shutdown, torque still on.
    wire.with_chain(|c| {
        let s = c.servo(5).unwrap();
        assert_eq!(s.hardware_error(), 0);
        assert!(s.torque_enabled());
        assert!(s.temperature_c() < 80.0, "{}", s.temperature_c());
    });
    assert_eq!(
        stop.to_string(),
        format!(
            "servo ID 5 (joint 4): {} degC, at or above the stop limit 75 degC",
            stop.value
        )
    );
}

//! The bus master against the virtual chain on the simulated wire: cycle timing against the wire
//! budget of ../shared/reference/dynamixel.md, per-servo faults, setup helpers.
#![cfg(feature = "std")]

use dynamixel::control_table as ct;
use dynamixel::instruction::StatusError;
use dynamixel::master::{BusError, Goal, MasterConfig, Reply, ReplyFault};
use dynamixel::sim::{Faults, SimMaster, SimWire, VirtualChain, WireConfig};

fn bus(return_delay_code: u8) -> (SimWire, SimMaster) {
    let wire = SimWire::drosophibot(22, 1_000_000, return_delay_code).unwrap();
    let master = wire.master(MasterConfig::new(1_000_000));
    (wire, master)
}

/// Servo 2's answer to a write it refuses with `status`.
fn servo_2_refuses(status: StatusError) -> BusError {
    BusError::Reply {
        id: 2,
        fault: ReplyFault::Status(status),
    }
}

fn goals(pos: i32) -> Vec<Goal> {
    (1..=22).map(|id| Goal { id, position: pos }).collect()
}

fn run_cycle(
    wire: &SimWire,
    m: &mut SimMaster,
    g: &[Goal],
) -> (Vec<Reply>, dynamixel::master::CycleStats) {
    let mut replies = vec![Err(ReplyFault::Timeout); g.len()];
    let stats = wire.block_on(m.cycle(g, &mut replies)).unwrap();
    (replies, stats)
}

#[test]
fn cycle_of_22_at_1mbps_takes_the_wire_time_of_622_bytes() {
    let (wire, mut m) = bus(0);
    let (replies, stats) = run_cycle(&wire, &mut m, &goals(2048));
    assert!(
        replies
            .iter()
            .all(|r| matches!(r, Ok(f) if f.position == 2048 && !f.alert)),
        "{replies:?}"
    );
    // dynamixel.md: 124 + 36 request bytes, 22 x 21 reply bytes = 622 bytes x 10 us at 1 Mbit/s.
    assert_eq!(stats.tx_end_us - stats.start_us, 1_600);
    assert_eq!(stats.duration_us(), 6_220);
    assert_eq!((stats.ok, stats.timeouts, stats.echo_frames), (22, 0, 2));
    assert_eq!(wire.byte_counts(), (160, 462));
}

#[test]
fn default_return_delay_adds_500_us_per_servo() {
    let (wire, mut m) = bus(250);
    let (_, stats) = run_cycle(&wire, &mut m, &goals(2048));
    // dynamixel.md: 6.22 ms + 22 x 500 us, i.e. the 58 Hz of the table.
    assert_eq!(stats.duration_us(), 6_220 + 22 * 500);
    assert_eq!(1_000_000 / stats.duration_us(), 58);
}

#[test]
fn faulty_servos_are_reported_and_the_others_still_arrive() {
    let (wire, mut m) = bus(0);
    wire.with_chain(|c| {
        c.set_faults(5, Faults::SILENT).unwrap();
        c.set_faults(7, Faults::BAD_CRC).unwrap();
        c.set_faults(12, Faults::late_by_us(300)).unwrap();
        c.trigger_overload(9).unwrap();
    });
    let (replies, stats) = run_cycle(&wire, &mut m, &goals(2048));
    assert_eq!(replies[4], Err(ReplyFault::Timeout));
    assert_eq!(replies[6], Err(ReplyFault::Crc));
    assert!(
        matches!(replies[8], Ok(f) if f.alert),
        "overload shows as Alert: {:?}",
        replies[8]
    );
    for (i, r) in replies.iter().enumerate() {
        if ![4, 6, 8].contains(&i) {
            assert!(
                matches!(r, Ok(f) if f.position == 2048 && !f.alert),
                "servo {} lost: {r:?}",
                i + 1
            );
        }
    }
    assert_eq!(
        (stats.ok, stats.timeouts, stats.crc_errors, stats.alerts),
        (20, 1, 1, 1)
    );
    // One reply fewer on the wire (21 bytes) and 300 us of lateness. Servo 22's reply is the
    // last of the schedule: once it is in, servo 5 (whose turn came before it) cannot come any
    // more, so the master does not wait for it.
    assert_eq!(stats.duration_us(), 6_220 - 210 + 300);
}

#[test]
fn a_reply_later_than_the_slack_times_out_alone() {
    let (wire, mut m) = bus(0);
    wire.with_chain(|c| c.set_faults(22, Faults::late_by_us(5_000)).unwrap());
    let (replies, stats) = run_cycle(&wire, &mut m, &goals(2048));
    assert_eq!(replies[21], Err(ReplyFault::Timeout));
    assert_eq!(stats.ok, 21);
    // The master gives up after its slack (1000 us) plus one reply's wire time (210 us).
    assert_eq!(stats.duration_us(), 6_220 - 210 + 1_000 + 210);
    // The late reply arrives after the master gave up; the next cycle discards it instead of
    // taking it for servo 22's new reply.
    wire.advance_us(10_000);
    let (replies, stats) = run_cycle(&wire, &mut m, &goals(2048));
    assert_eq!(stats.stale_bytes, 21);
    assert!(replies[..21].iter().all(|r| r.is_ok()));
    assert_eq!(replies[21], Err(ReplyFault::Timeout));
}

#[test]
fn overload_clears_torque_and_alerts_until_reboot() {
    let (wire, mut m) = bus(0);
    wire.block_on(m.write(3, ct::TORQUE_ENABLE.addr, &[1]))
        .unwrap();
    wire.with_chain(|c| c.trigger_overload(3).unwrap());
    let mut b = [0u8; 1];
    let err = wire
        .block_on(m.read(3, ct::TORQUE_ENABLE.addr, &mut b))
        .unwrap();
    assert!(err.alert());
    assert_eq!(b[0], 0, "torque must be off after an overload");
    wire.block_on(m.read(3, ct::HARDWARE_ERROR_STATUS.addr, &mut b))
        .unwrap();
    assert_eq!(b[0], ct::hardware_error::OVERLOAD);
    // Torque cannot come back without a reboot.
    let e = wire
        .block_on(m.write(3, ct::TORQUE_ENABLE.addr, &[1]))
        .unwrap_err();
    assert!(
        matches!(e, BusError::Reply { id: 3, fault: ReplyFault::Status(s) } if s.alert() && s.0 & 0x7F == StatusError::RESULT_FAIL)
    );
    wire.block_on(m.reboot(3)).unwrap();
    let err = wire
        .block_on(m.read(3, ct::HARDWARE_ERROR_STATUS.addr, &mut b))
        .unwrap();
    assert!(!err.alert());
    assert_eq!(b[0], 0);
    assert!(
        wire.block_on(m.write(3, ct::TORQUE_ENABLE.addr, &[1]))
            .unwrap()
            .0
            == 0
    );
}

#[test]
fn ping_read_write_and_their_errors() {
    let (wire, mut m) = bus(0);
    let p = wire.block_on(m.ping(3)).unwrap();
    assert_eq!(p.model_number, 311, "CTr servo is an MX-64(2.0)");
    assert_eq!(
        wire.block_on(m.ping(1)).unwrap().model_number,
        30,
        "MX-28(2.0)"
    );
    assert!(matches!(
        wire.block_on(m.ping(40)),
        Err(BusError::Reply {
            id: 40,
            fault: ReplyFault::Timeout
        })
    ));
    wire.block_on(m.write(2, ct::GOAL_POSITION.addr, &1000u32.to_le_bytes()))
        .unwrap();
    let mut b = [0u8; 4];
    wire.block_on(m.read(2, ct::GOAL_POSITION.addr, &mut b))
        .unwrap();
    assert_eq!(u32::from_le_bytes(b), 1000);
    // Goal beyond Max Position Limit (4095): Data Limit error, nothing written.
    let e = wire
        .block_on(m.write(2, ct::GOAL_POSITION.addr, &5000u32.to_le_bytes()))
        .unwrap_err();
    assert_eq!(e, servo_2_refuses(StatusError(6)));
    // EEPROM with torque on: Access error.
    wire.block_on(m.write(2, ct::TORQUE_ENABLE.addr, &[1]))
        .unwrap();
    let e = wire
        .block_on(m.write(2, ct::RETURN_DELAY_TIME.addr, &[0]))
        .unwrap_err();
    assert_eq!(e, servo_2_refuses(StatusError(7)));
}

#[test]
fn sync_and_bulk_helpers() {
    let (wire, mut m) = bus(0);
    let ids = [1u8, 3, 5];
    let mut data = [0u8; 6];
    let mut out = [Err(ReplyFault::Timeout); 3];
    wire.block_on(m.sync_read(ct::MODEL_NUMBER.addr, 2, &ids, &mut data, &mut out))
        .unwrap();
    assert!(out.iter().all(|o| o.is_ok()));
    assert_eq!(
        [
            u16::from_le_bytes([data[0], data[1]]),
            u16::from_le_bytes([data[2], data[3]])
        ],
        [30, 311]
    );
    let v = 1500u32.to_le_bytes();
    wire.block_on(m.bulk_write([
        (1, ct::GOAL_POSITION.addr, &v[..]),
        (2, ct::LED.addr, &[1][..]),
    ]))
    .unwrap();
    let mut data = [0u8; 5];
    let mut out = [Err(ReplyFault::Timeout); 2];
    wire.block_on(m.bulk_read(
        &[(1, ct::GOAL_POSITION.addr, 4), (2, ct::LED.addr, 1)],
        &mut data,
        &mut out,
    ))
    .unwrap();
    assert_eq!(out, [Ok(StatusError(0)), Ok(StatusError(0))]);
    assert_eq!(
        (u32::from_le_bytes(data[..4].try_into().unwrap()), data[4]),
        (1500, 1)
    );
}

/// Runs cycles at a 10 ms period for `ms` milliseconds of simulated time.
fn run_for(wire: &SimWire, m: &mut SimMaster, g: &[Goal], ms: u64) -> Vec<Reply> {
    let mut last = Vec::new();
    for _ in 0..ms / 10 {
        let t0 = wire.now_us();
        last = run_cycle(wire, m, g).0;
        wire.advance_us(10_000 - (wire.now_us() - t0));
    }
    last
}

fn torque_on(wire: &SimWire, m: &mut SimMaster) {
    let on = [1u8];
    wire.block_on(m.sync_write(ct::TORQUE_ENABLE.addr, 1, (1..=22).map(|id| (id, &on[..]))))
        .unwrap();
}

#[test]
fn a_large_step_moves_at_the_no_load_speed_and_settles_on_the_goal() {
    let (wire, mut m) = bus(0);
    torque_on(&wire, &mut m);
    let g = goals(3048);
    let r = run_for(&wire, &mut m, &g, 50);
    // MX-28 datasheet: 55 rev/min no-load; Present Velocity unit 0.229 rev/min -> 240 units.
    let v = r[0].unwrap().velocity;
    assert!((238..=241).contains(&v), "velocity {v}");
    let r = run_for(&wire, &mut m, &g, 1_000);
    assert!(
        r.iter().all(|x| (x.unwrap().position - 3048).abs() <= 1),
        "{r:?}"
    );
}

#[test]
fn external_torque_deflects_like_the_documented_spring_and_shows_as_load() {
    let (wire, mut m) = bus(0);
    torque_on(&wire, &mut m);
    wire.with_chain(|c| {
        c.set_external_torque(1, 1.0).unwrap();
        c.set_external_torque(3, 1.0).unwrap();
    });
    let r = run_for(&wire, &mut m, &goals(2048), 1_000);
    // Hand calculation, P = 850: Kp = 850/128 = 6.64 PWM/tick; 885 PWM = stall torque.
    // MX-28: 6.64/885 * 2.5 N m = 0.01876 N m/tick -> 1 N m deflects 53.3 ticks; load = 1/2.5 = 40.0 %.
    // MX-64: 6.64/885 * 6.0 = 0.04502 N m/tick -> 22.2 ticks; current 1/6.0 * 4.1 A = 683 mA = 203 units.
    for (servo, model, deflection, unit, load) in [
        (1, "MX-28", 53, "load", -400),
        (3, "MX-64", 22, "current", -203),
    ] {
        let f = r[servo - 1].unwrap();
        assert!(
            (f.position - (2048 + deflection)).abs() <= 1,
            "{model} deflection {}",
            f.position - 2048
        );
        assert!((f.load - load).abs() <= 2, "{model} {unit} {}", f.load);
    }
}

#[test]
fn a_stuck_servo_stays_and_strains() {
    let (wire, mut m) = bus(0);
    torque_on(&wire, &mut m);
    wire.with_chain(|c| c.set_faults(2, Faults::JAMMED).unwrap());
    let mut g = goals(2048);
    g[1].position = 2148;
    let r = run_for(&wire, &mut m, &g, 200);
    let f = r[1].unwrap();
    assert_eq!((f.position, f.velocity), (2048, 0));
    // Stalled motor: PWM 6.64 * 100 / 885 = 75.0 % of stall torque -> load 750 (0.1 % units).
    assert!((f.load - 750).abs() <= 2, "load {}", f.load);
}

#[test]
fn garbage_before_the_replies_is_skipped_and_counted() {
    let (wire, mut m) = bus(0);
    // Noise that looks like the start of headers, arriving while the request goes out.
    wire.inject_noise(&[0xFF, 0xFF, 0xFD, 0x12, 0xFF, 0xFF, 0x00, 0x55, 0xAA]);
    let (replies, stats) = run_cycle(&wire, &mut m, &goals(2048));
    assert!(replies.iter().all(|r| r.is_ok()), "{replies:?}");
    // The noise lands on the echo of the Sync Write (124 bytes), which is lost with it; the Sync
    // Read's echo (36 bytes) after it is intact.
    assert_eq!((stats.garbage_bytes, stats.echo_frames), (9 + 124, 1));
}

#[test]
fn without_echo_no_instruction_frames_are_seen() {
    let mut chain = VirtualChain::drosophibot(22, 1_000_000).unwrap();
    chain.set_return_delay_all(0);
    let wire = SimWire::new(
        chain,
        WireConfig {
            baud: 1_000_000,
            echo: false,
        },
    );
    let mut m = wire.master(MasterConfig::new(1_000_000));
    let (replies, stats) = run_cycle(&wire, &mut m, &goals(2048));
    assert!(replies.iter().all(|r| r.is_ok()));
    assert_eq!((stats.echo_frames, stats.duration_us()), (0, 6_220));
}

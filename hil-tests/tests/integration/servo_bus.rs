//! The servo chain process's lock-step side against the Dynamixel e-manual: a PING to ID 1 (the
//! manual's example packet) is answered by one status packet carrying the MX-28(2.0) model number
//! 30, after the Return Delay Time; a broadcast write gets no answer; a packet split across bursts
//! is still executed.

use dynamixel::sim::VirtualChain;
use hil_tests::servo_bus::ServoBus;
use serde_json::Value;

const PING_1: [u8; 10] = [0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x03, 0x00, 0x01, 0x19, 0x4E];

/// The robot's 22 servos as its model file maps them.
fn robot_chain() -> VirtualChain {
    VirtualChain::new(&hil_tests::gait::robot_servos(), 1_000_000).unwrap()
}

fn bus(return_delay: u8) -> ServoBus {
    let mut chain = robot_chain();
    chain.set_return_delay_all(return_delay);
    ServoBus::new(chain)
}

#[test]
fn ping_is_answered_with_the_model_number_after_the_return_delay() {
    let mut b = bus(250);
    let replies = b.burst(&PING_1, 100_000, 1_000_000);
    assert_eq!(replies.len(), 1);
    let r = &replies[0];
    // Return Delay Time 250 x 2 us = 500 us.
    assert_eq!(r.delay_ns, 500_000);
    assert_eq!(r.rx.len(), 14);
    assert_eq!(
        r.rx[..9],
        [0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x07, 0x00, 0x55, 0x00]
    );
    assert_eq!(
        u16::from_le_bytes([r.rx[9], r.rx[10]]),
        30,
        "MX-28(2.0) model number"
    );
}

#[test]
fn turnaround_adds_to_the_return_delay() {
    let chain = robot_chain();
    let mut b = ServoBus::new(chain).with_turnaround(std::time::Duration::from_micros(20));
    let replies = b.burst(&PING_1, 100_000, 1_000_000);
    // Factory Return Delay Time 250 x 2 us = 500 us, plus 20 us.
    assert_eq!(replies[0].delay_ns, 520_000);
}

#[test]
fn a_packet_split_across_bursts_is_executed_once_complete() {
    let mut b = bus(0);
    assert!(b.burst(&PING_1[..4], 10_000, 1_000_000).is_empty());
    let replies = b.burst(&PING_1[4..], 20_000, 1_000_000);
    assert_eq!(replies.len(), 1);
    assert_eq!(replies[0].delay_ns, 0);
}

#[test]
fn runner_lines_round_trip_and_bad_lines_are_errors() {
    let mut b = bus(0);
    let hex: String = PING_1.iter().map(|x| format!("{x:02x}")).collect();
    let line = format!(r#"{{"tx":"{hex}","start_ns":0,"end_ns":100000,"baud":1000000}}"#);
    let answer: Value = serde_json::from_str(&b.line(&line).unwrap().unwrap()).unwrap();
    assert_eq!(answer["segments"].as_array().unwrap().len(), 1);
    assert!(b.line(r#"{"control":{"overload":1}}"#).unwrap().is_none());
    assert!(
        b.line(r#"{"control":{"overload":99}}"#).is_err(),
        "no servo 99"
    );
    assert!(b.line("not json").is_err());
    assert!(
        b.line(r#"{"tx":"abc","end_ns":0,"baud":1}"#).is_err(),
        "odd hex"
    );
}

//! Servo reads through the board (`ReadServo` / `GetServoRead`, protocol version 9), on the
//! dynamixel crate's virtual chain: the board reads the register bytes the servo holds (the
//! e-manual's Model Number: 30 for an MX-28(2.0), 311 for an MX-64(2.0)), pings, reports a servo
//! that is not there as a timeout, refuses an ID or length it cannot read, and reads while walking
//! without a missed cycle start.

use dynamixel::sim::DROSOPHIBOT_CTR_IDS;
use firmware::testkit::SyntheticGait;
use firmware::testkit::rig::{self, ask, cycle, status};
use protocol::{
    Client, ProtocolError, Request, Response, ServoRead, ServoReadOutcome, ServoReadResult, Setting,
};

/// Asks for `read`, runs bus cycles until it is done (at most 10), returns its outcome.
fn read(
    board: &mut rig::SimBoard,
    wire: &dynamixel::sim::SimWire,
    client: &mut Client,
    read: ServoRead,
) -> ServoReadOutcome {
    assert_eq!(ask(board, client, Request::ReadServo(read)), Response::Ack);
    for _ in 0..10 {
        cycle(board, wire);
        match ask(board, client, Request::GetServoRead) {
            Response::ServoRead(Some(ServoReadResult { request, outcome })) => {
                assert_eq!(request, read);
                return outcome;
            }
            Response::ServoRead(None) => {}
            other => panic!("GetServoRead answered {other:?}"),
        }
    }
    panic!("{read:?} not done in 10 bus cycles");
}

fn model_number(outcome: ServoReadOutcome) -> u16 {
    match outcome {
        ServoReadOutcome::Data { error: 0, data } => u16::from_le_bytes([data[0], data[1]]),
        other => panic!("{other:?}"),
    }
}

#[test]
fn the_board_reads_and_pings_its_servos_for_the_host() {
    let table = SyntheticGait::new(100, 1.0).build();
    let (mut board, wire, mut client) = rig::walking(1_000_000, 100, &table);
    let before = status(&mut board, &mut client).counters;
    let mx64 = DROSOPHIBOT_CTR_IDS[0];
    // Model Number (address 0, 2 bytes), while the robot walks.
    let at = |id| ServoRead {
        id,
        addr: 0,
        len: 2,
    };
    assert_eq!(
        model_number(read(&mut board, &wire, &mut client, at(1))),
        30
    );
    assert_eq!(
        model_number(read(&mut board, &wire, &mut client, at(mx64))),
        311
    );
    // A ping: the same number, and the firmware version the virtual servo carries.
    match read(
        &mut board,
        &wire,
        &mut client,
        ServoRead {
            id: mx64,
            addr: 0,
            len: 0,
        },
    ) {
        ServoReadOutcome::Ping {
            error: 0,
            model_number: 311,
            ..
        } => {}
        other => panic!("{other:?}"),
    }
    // No servo 30 on the bus.
    assert_eq!(
        read(&mut board, &wire, &mut client, at(30)),
        ServoReadOutcome::Timeout
    );
    // The reads cost the walk no cycle start.
    let after = status(&mut board, &mut client).counters;
    assert_eq!(after.missed_deadlines, before.missed_deadlines);
    assert!(after.cycles > before.cycles);
    // What the board cannot read is refused naming the setting and the value.
    for (bad, value) in [
        (
            ServoRead {
                id: 0xFE,
                addr: 0,
                len: 2,
            },
            0xFE,
        ),
        (
            ServoRead {
                id: 1,
                addr: 0,
                len: 33,
            },
            33,
        ),
    ] {
        assert_eq!(
            ask(&mut board, &mut client, Request::ReadServo(bad)),
            Response::Error(ProtocolError::InvalidSetting {
                setting: Setting::ServoRead,
                value
            })
        );
    }
}

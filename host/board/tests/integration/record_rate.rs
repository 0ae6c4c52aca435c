//! A telemetry rate the recorder's silence limit cannot serve is refused before recording
//! (issue 30 item 4: `record --every 300` recorded a few rows, then failed as "no telemetry for
//! 2 s", and replaced a good recording with them).

use board::link::Board;
use board::record::{CaptureError, check_telemetry_rate, set_recording_rate};
use board::robot::{VirtualRobot, VirtualTransport};

#[test]
fn a_rate_the_silence_limit_cannot_serve_is_refused_naming_both_numbers() {
    // At 100 Hz a record every 199 cycles comes every 1.99 s, under the 2 s limit; 200 would
    // reach it exactly and 300 (3 s) is over it.
    check_telemetry_rate(1, 100).unwrap();
    check_telemetry_rate(199, 100).unwrap();
    for every in [200, 300, u16::MAX] {
        let e = check_telemetry_rate(every, 100).unwrap_err();
        assert!(
            matches!(e, CaptureError::RateTooLow { max_every: 199, .. }),
            "{e}"
        );
        let text = e.to_string();
        for n in [
            every.to_string(),
            "100 Hz".into(),
            "2 s".into(),
            "199".into(),
        ] {
            assert!(text.contains(&n), "`{text}` lacks `{n}`");
        }
    }
    // At 200 Hz twice as many cycles fit: 399.
    check_telemetry_rate(399, 200).unwrap();
    check_telemetry_rate(400, 200).unwrap_err();
}

#[test]
fn the_board_keeps_its_rate_when_the_new_one_is_refused() {
    let mut b = Board::connect(VirtualTransport::new(VirtualRobot::new())).unwrap();
    set_recording_rate(&mut b, 5).unwrap();
    assert_eq!(b.settings().unwrap().telemetry_every, 5);
    set_recording_rate(&mut b, 300).unwrap_err();
    assert_eq!(b.settings().unwrap().telemetry_every, 5);
}

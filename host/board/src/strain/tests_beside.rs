//! [`StrainBeside`] against the in-process virtual board (paced like the real one): the rows it
//! keeps when the board hangs up or garbles a line mid-recording, aligned on the clock the test's
//! own telemetry stand-in gives (board time = host time since a known instant, by construction).

use std::os::unix::net::UnixStream;
use std::time::{Duration, Instant};

use super::beside::{CLOCK_CSV, read_aligned};
use super::source::Constant;
use super::tests::{board_on_a_socket, quick};
use super::*;

const PORT: &str = "/dev/ttyACM7";

fn paced_board(faults: Vec<Fault>) -> UnixStream {
    board_on_a_socket(Box::new(Constant(0.0)), faults, true)
}

/// Notes a telemetry record every 10 ms for `seconds` of host time, the board's clock starting
/// at `t0`; returns `t0`.
fn telemetry_for(s: &mut StrainBeside, seconds: f64) -> Instant {
    let t0 = Instant::now();
    while t0.elapsed().as_secs_f64() < seconds {
        s.note(t0.elapsed().as_secs_f64());
        std::thread::sleep(Duration::from_millis(10));
    }
    t0
}

#[test]
fn a_board_that_hangs_up_mid_recording_leaves_its_rows_aligned() {
    let dir = tempfile::tempdir().unwrap();
    let io = paced_board(vec![Fault::HangUpAt(6)]);
    let mut s = StrainBeside::start_on(Box::new(io), PORT, dir.path(), quick()).unwrap();
    assert!(s.samples() >= 1, "start returns after the first sample");
    // The servo side keeps going long after the strain board is gone (6 samples: ~0.15 s).
    telemetry_for(&mut s, 0.4);
    assert!(s.failed());
    let end = s.finish();
    let e = end.recording.unwrap_err();
    assert_eq!(e.samples, 6);
    assert!(
        e.to_string()
            .contains(&format!("{PORT}: the strain board went away")),
        "{e}"
    );
    let fit = end.clock.unwrap().unwrap();
    // Board time is host time since t0 by construction: a rate of 1 (sleep jitter aside).
    assert!((fit.rate - 1.0).abs() < 0.05, "{}", fit.rate);
    let text = std::fs::read_to_string(dir.path().join("strain.csv")).unwrap();
    assert!(text.starts_with("time_s,host_s,LH_troch_axial,"), "{text}");
    let a = read_aligned(&dir.path().join("strain.csv")).unwrap();
    assert_eq!(a.counts.len(), 6);
    assert!(a.counts.iter().all(|r| r.iter().all(|&c| c == 300.0)));
    // The samples came before the servo clock's zero (they end ~0.15 s after the start, t0 is
    // after the first one): times are increasing, the first one negative.
    let t: Vec<f64> = a.time_s.iter().map(|t| t.unwrap()).collect();
    assert!(t[0] < 0.0, "{t:?}");
    assert!(t.windows(2).all(|w| w[1] > w[0]), "{t:?}");
    let clock = std::fs::read_to_string(dir.path().join(CLOCK_CSV)).unwrap();
    assert!(clock.starts_with("host_s_per_board_s,host_s_at_board_0,records,jitter_p95_s\n"));
}

#[test]
fn a_garbled_line_mid_recording_ends_the_strain_stream_naming_the_gauge() {
    let dir = tempfile::tempdir().unwrap();
    let io = paced_board(vec![Fault::GarbageAt(4)]);
    let mut s = StrainBeside::start_on(Box::new(io), PORT, dir.path(), quick()).unwrap();
    telemetry_for(&mut s, 0.3);
    let end = s.finish();
    let e = end.recording.unwrap_err();
    assert_eq!(e.samples, 4);
    // Column 8 is board leg 1 (RH), gauge 1: the trochanter's transverse gauge.
    let msg = e.to_string();
    assert!(msg.contains("column 8, RH_troch_transverse"), "{msg}");
    assert!(msg.contains("`3?0.00` is not a number"), "{msg}");
    assert_eq!(
        read_aligned(&dir.path().join("strain.csv"))
            .unwrap()
            .counts
            .len(),
        4
    );
}

#[test]
fn the_servo_boards_port_is_refused_before_anything_starts() {
    let dir = tempfile::tempdir().unwrap();
    let e = StrainBeside::start("/dev/ttyACM0", "/dev/ttyACM0", dir.path()).unwrap_err();
    assert_eq!(
        e.to_string(),
        "/dev/ttyACM0 is the servo board's port; the strain board has a port of its own (`dbot \
         devices` lists the servo board)"
    );
    assert!(!dir.path().join("strain.csv").exists());
}

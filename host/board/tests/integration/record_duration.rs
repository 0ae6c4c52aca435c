//! A recording's length is counted in the board's records, not in CSV rows (issue #30 item 2):
//! `dbot record --seconds 1 --port physics` on a board that reports no joints (a physics robot
//! with no gait) wrote records of zero rows, so its length stayed 0 s and the recording ran on
//! for ever (26 000 s of simulated time in ten minutes, found with gdb).

use board::record::Recorder;
use protocol::{BusStats, Telemetry};

fn record(time_us: u64, cycle: u32) -> Telemetry {
    Telemetry {
        time_us,
        cycle,
        step: 0,
        slice: 0,
        joints: heapless::Vec::new(),
        bus: BusStats::default(),
        platform: None,
        state: protocol::RunState::Walking,
        health: heapless::Vec::new(),
    }
}

#[test]
fn records_without_joints_still_count_time_and_cycles() {
    let dir = tempfile::tempdir().unwrap();
    let mut rec = Recorder::create(&dir.path().join("t.csv"), Vec::new()).unwrap();
    assert_eq!(rec.duration_s(), 0.0);
    // Three bus cycles 10 ms apart, from board time 5 s: 20 ms after the first.
    for k in 0..3u32 {
        rec.push(&record(5_000_000 + u64::from(k) * 10_000, 100 + k))
            .unwrap();
    }
    assert_eq!(rec.cycles(), 3);
    assert!(
        (rec.duration_s() - 0.020).abs() < 1e-12,
        "{}",
        rec.duration_s()
    );
}

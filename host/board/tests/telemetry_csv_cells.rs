//! telemetry.csv leaves a cell empty where there is no value (issue 20 item 7): a torque-off row
//! carries no goal (the firmware's goal register then holds -pi, which is not a command).

use board::record::{JointMeta, Recorder};
use protocol::{BusStats, JointFeedback, ServoHealth, Telemetry, feedback_flags};

#[test]
fn torque_off_rows_have_an_empty_goal() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.csv");
    let mut rec = Recorder::create(
        &path,
        vec![JointMeta::named("LF_ThC1"), JointMeta::named("LF_ThC2")],
    )
    .unwrap();
    let fb = |flags| JointFeedback {
        commanded: -31415,
        present: 5000,
        velocity: 0,
        load: 0,
        error: 0,
        flags,
    };
    let mut joints = heapless::Vec::new();
    joints.push(fb(feedback_flags::TORQUE_OFF)).unwrap();
    joints.push(fb(0)).unwrap();
    rec.push(&Telemetry {
        time_us: 10,
        cycle: 1,
        step: 0,
        slice: 0,
        joints,
        bus: BusStats::default(),
        platform: None,
        // Joint 0 not read yet; joint 1's servo at 47 degC on 11.8 V.
        health: [
            ServoHealth::default(),
            ServoHealth {
                temperature_c: 47,
                voltage_dv: 118,
            },
        ]
        .into_iter()
        .collect(),
    })
    .unwrap();
    drop(rec);
    let mut rd = csv::Reader::from_path(&path).unwrap();
    let col = rd
        .headers()
        .unwrap()
        .iter()
        .position(|h| h == "commanded_rad")
        .unwrap();
    let rows: Vec<csv::StringRecord> = rd.records().map(|r| r.unwrap()).collect();
    assert_eq!(&rows[0][4], "LF_ThC1");
    assert_eq!(&rows[0][col], "", "torque off: no goal");
    // Torque on: the goal, 1e-4 rad units, to four decimals.
    assert_eq!(&rows[1][col], "-3.1415");
    assert_eq!(&rows[1][7], "0.5000");
    // Heat and supply: empty until the servo is first read, then degC and V.
    assert_eq!((&rows[0][17], &rows[0][18]), ("", ""));
    assert_eq!((&rows[1][17], &rows[1][18]), ("47", "11.8"));
}

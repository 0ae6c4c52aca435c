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
        state: protocol::RunState::Walking,
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
    let (col, rows) = column_and_rows(&path, "commanded_rad");
    assert_eq!(&rows[0][4], "LF_ThC1");
    assert_eq!(&rows[0][col], "", "torque off: no goal");
    // Torque on: the goal, 1e-4 rad units, to four decimals.
    assert_eq!(&rows[1][col], "-3.1415");
    assert_eq!(&rows[1][7], "0.5000");
    // Heat and supply: empty until the servo is first read, then degC and V (after run_state).
    assert_eq!((&rows[0][18], &rows[0][19]), ("", ""));
    assert_eq!((&rows[1][18], &rows[1][19]), ("47", "11.8"));
}

/// One torque-on record of one joint: goal 0.3000 rad, slice 0, in `state`.
fn one_record(state: protocol::RunState) -> Telemetry {
    let mut joints = heapless::Vec::new();
    joints
        .push(JointFeedback {
            commanded: 3000,
            present: 2900,
            velocity: 0,
            load: 0,
            error: 0,
            flags: 0,
        })
        .unwrap();
    Telemetry {
        time_us: 10,
        cycle: 7,
        step: 0,
        slice: 0,
        joints,
        bus: BusStats::default(),
        platform: None,
        state,
        health: heapless::Vec::new(),
    }
}

/// The planned angle of a row is the goal less the bias torque / k at the k the board held (issue
/// 43 item 3), not the table's: a table at 5 N m/rad played after `dbot set --stiffness` to 2.5,
/// and to 0 (bias off: the goal is the plan). Hand calculation: 0.3 - 0.5 / 2.5 = 0.1.
#[test]
fn planned_angle_subtracts_the_bias_at_the_stiffness_the_board_held() {
    let planned = |held: Option<u32>| {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.csv");
        let mut joint = JointMeta::named("LF_ThC1");
        joint.modelled_nm = vec![0.5];
        joint.planned_rad = vec![0.2];
        joint.stiffness_nm_per_rad = Some(5.0);
        let mut joints = vec![joint];
        if let Some(k) = held {
            let settings = protocol::Settings {
                baud: 1_000_000,
                cycle_hz: 100,
                telemetry_every: 1,
                joints: [protocol::JointSettings {
                    stiffness: k,
                    min: -30000,
                    max: 30000,
                    torque_enabled: true,
                }]
                .into_iter()
                .collect(),
                health: protocol::HealthLimits::DEFAULT,
            };
            board::record::held_stiffness(&mut joints, &settings);
        }
        let mut rec = Recorder::create(&path, joints).unwrap();
        rec.push(&one_record(protocol::RunState::Walking)).unwrap();
        rec.rows()[0].planned_rad.unwrap()
    };
    // The table's stiffness: 0.3 - 0.5 / 5 = 0.2.
    assert!((planned(None) - 0.2).abs() < 1e-9);
    assert!(
        (planned(Some(2500)) - 0.1).abs() < 1e-9,
        "{}",
        planned(Some(2500))
    );
    assert!(
        (planned(Some(0)) - 0.3).abs() < 1e-9,
        "{}",
        planned(Some(0))
    );
}

/// Every row carries the board's run state (issue 43 item 3): a fault shows in the recording.
#[test]
fn rows_carry_the_boards_run_state() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.csv");
    let mut rec = Recorder::create(&path, vec![JointMeta::named("LF_ThC1")]).unwrap();
    rec.push(&one_record(protocol::RunState::Walking)).unwrap();
    rec.push(&one_record(protocol::RunState::Fault)).unwrap();
    drop(rec);
    let (col, rows) = column_and_rows(&path, "run_state");
    let states: Vec<&str> = rows.iter().map(|r| &r[col]).collect();
    assert_eq!(states, ["Walking", "Fault"]);
}

/// The index of the column named `name` in the CSV at `path`, and its rows.
fn column_and_rows(path: &std::path::Path, name: &str) -> (usize, Vec<csv::StringRecord>) {
    let mut rd = csv::Reader::from_path(path).unwrap();
    let col = rd
        .headers()
        .unwrap()
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"));
    (col, rd.records().map(|r| r.unwrap()).collect())
}

//! Trial records (issue 29 item 1): a trial written and read back with every metadata field, two
//! trials in a row never sharing a folder, a folder that exists or cannot be made refused before
//! anything is written, and how a trial that ended early is named.

use std::path::Path;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use board::link::Board;
use board::record::{Recorder, Until, capture, joints_of_table};
use board::robot::{VirtualRobot, VirtualTransport};
use board::trial::{
    BoardSettings, FirmwareMeta, GaitMeta, INDEX_TXT, JointSetting, Outcome, Perturbation,
    PlanMeta, Substrate, TELEMETRY_CSV, TRIAL_FORMAT, TrialError, TrialFolder, TrialMeta,
    latest_trial, list_trials, read_trial,
};
use firmware::testkit::SyntheticGait;
use protocol::{Direction, GaitTable, PlayCommand, Steps};

/// 2026-12-02 06:30:05 UTC (`date -u -d @1796193005`).
fn start() -> SystemTime {
    UNIX_EPOCH + Duration::from_secs(1_796_193_005)
}

/// A metadata value with every field set to something other than its default.
fn meta(joints: Vec<String>) -> TrialMeta {
    TrialMeta {
        format_version: TRIAL_FORMAT,
        folder: String::new(),
        outcome: Outcome::Complete,
        fault: None,
        started: "2026-12-02T06:30:05Z".into(),
        host_version: "9.8.7".into(),
        command_line: vec![
            "dbot".into(),
            "record".into(),
            "--notes".into(),
            "a b".into(),
        ],
        port: "virtual".into(),
        firmware: FirmwareMeta {
            version: "1.2.3".into(),
            protocol_version: 4,
            table_format_version: 2,
            build_id: 0xdead_beef,
        },
        settings: BoardSettings {
            bus_baud: 1_000_000,
            cycle_hz: 100,
            telemetry_every: 1,
            joints: vec![JointSetting {
                stiffness_mnm_per_rad: 8400,
                min_1e4_rad: -15_000,
                max_1e4_rad: 15_000,
                torque_enabled: true,
            }],
        },
        gait: Some(GaitMeta {
            slot: Some(2),
            name: "tripod".into(),
            crc: 0x1234_5678,
            joints: 22,
            slices: 40,
            step_period_s: 0.6,
            duty: 0.5,
        }),
        plan: Some(PlanMeta {
            dir: "out/walk".into(),
            model: "drosophibot2".into(),
            model_source: "drosophibot2".into(),
            model_crc: "0badf00d".into(),
            parameters: serde_json::json!({"swing_s": 0.4}),
            period_s: 0.6,
        }),
        direction: Some(Direction::Backward),
        period_scale: Some(1.5),
        steps: Some(3),
        substrate: Substrate::WireMesh,
        strain: true,
        perturbation: Some(Perturbation {
            leg: "RM".into(),
            step: 2,
            rest: 2020,
            moved_to: 2330,
            platform_id: Some(23),
        }),
        notes: "sand paper, second try".into(),
        joints,
        cycles: 0,
        duration_s: 0.0,
        missing_records: 0,
        lost_records: Some(0),
    }
}

/// Records a 2-step walk of the virtual robot into `folder`; returns the rows' joints' names.
fn record_walk(folder: &TrialFolder) -> (Vec<String>, Recorder) {
    let gait = SyntheticGait::new(40, 0.6).build();
    let table = GaitTable::parse(&gait).unwrap();
    let mut b = Board::connect(VirtualTransport::new(VirtualRobot::new())).unwrap();
    gate::upload(&mut b, 0, &gait).unwrap();
    gate::play(&mut b, PlayCommand::forward(0, Steps::Count(2))).unwrap();
    let names: Vec<String> = (0..22).map(|j| format!("JOINT{j}")).collect();
    let mut rec = Recorder::create(
        &folder.work_dir().join(TELEMETRY_CSV),
        joints_of_table(&table, &names),
    )
    .unwrap();
    let until = Until {
        seconds: None,
        standing: true,
    };
    capture(&mut b, &mut rec, until, |_| {}).unwrap();
    (names, rec)
}

#[test]
fn a_trial_is_read_back_with_every_field_and_every_row() {
    let dir = tempfile::tempdir().unwrap();
    let trials = dir.path().join("trials");
    let folder = TrialFolder::begin(&trials, None, start()).unwrap();
    // While it records, the trial is a hidden folder: no reader takes it for finished.
    assert_eq!(
        folder.work_dir(),
        trials.join(".partial-2026-12-02 06_30_05")
    );
    let (names, rec) = record_walk(&folder);
    let mut written = meta(names);
    written.cycles = rec.cycles();
    written.duration_s = rec.duration_s();
    written.missing_records = 3;
    let path = folder.publish(&mut written).unwrap();
    assert_eq!(path, trials.join("2026-12-02 06_30_05"));
    assert_eq!(written.folder, "2026-12-02 06_30_05");
    assert!(!trials.join(".partial-2026-12-02 06_30_05").exists());

    let t = read_trial(&path).unwrap();
    // Every field, as written (the struct's equality covers each of them).
    assert_eq!(t.meta, written);
    assert_eq!(t.meta.perturbation.as_ref().unwrap().leg, "RM");
    assert_eq!(t.meta.plan.as_ref().unwrap().parameters["swing_s"], 0.4);
    assert!(t.meta.strain);
    // Every row, to the CSV's printed precision (time 1e-6 s, angles 1e-4 rad, velocity 1e-3).
    assert_eq!(t.rows.len(), rec.rows().len());
    // 22 rows for each bus cycle that has rows; `cycles()` also counts the records of the board's
    // first cycles in Boot (the upload selected new servos), which have no joints and no rows.
    let with_rows: std::collections::BTreeSet<_> = t.rows.iter().map(|r| r.cycle).collect();
    assert_eq!(t.rows.len(), with_rows.len() * 22);
    assert!(with_rows.len() <= rec.cycles() && with_rows.len() + 5 >= rec.cycles());
    for (a, b) in t.rows.iter().zip(rec.rows()) {
        assert_eq!(
            (a.cycle, a.step, a.slice, a.joint),
            (b.cycle, b.step, b.slice, b.joint)
        );
        assert!((a.time_s - b.time_s).abs() <= 5e-7);
        assert!((a.present_rad - b.present_rad).abs() <= 5e-5);
        // Torque off: the goal cell is empty (no goal driven), read back as NaN.
        if b.flags & protocol::feedback_flags::TORQUE_OFF != 0 {
            assert!(a.commanded_rad.is_nan());
        } else {
            assert!((a.commanded_rad - b.commanded_rad).abs() <= 5e-5);
        }
        assert!((a.velocity_rad_s - b.velocity_rad_s).abs() <= 5e-4);
        assert_eq!(
            (a.load_raw, a.error, a.flags, a.bus_cycle_us),
            (b.load_raw, b.error, b.flags, b.bus_cycle_us)
        );
        assert_eq!(a.modelled_nm.is_some(), b.modelled_nm.is_some());
    }
    // The README says what the lab's READMEs say; the index has the trial's line.
    let readme = std::fs::read_to_string(path.join("README.md")).unwrap();
    for needle in [
        "direction: backward",
        "substrate: wire-mesh",
        "step period: 0.900 s",
        "strain recorded: yes",
        "perturbation: leg RM at step 2, platform servo ID 23, 2020 -> 2330 ticks",
        "notes: sand paper, second try",
        "| `present_rad` |",
    ] {
        assert!(
            readme.contains(needle),
            "README lacks `{needle}`:\n{readme}"
        );
    }
    let index = std::fs::read_to_string(trials.join(INDEX_TXT)).unwrap();
    assert_eq!(index.lines().count(), 1);
    assert!(index.starts_with("2026-12-02 06_30_05\tcomplete\tgait tripod (CRC 12345678)"));
    assert_eq!(latest_trial(&trials).unwrap(), Some(path));
}

/// Publishes an empty-bodied trial (a header-only CSV) begun at `start()`.
fn publish(trials: &Path, name: Option<&str>, outcome: Outcome) -> std::path::PathBuf {
    let folder = TrialFolder::begin(trials, name, start()).unwrap();
    std::fs::write(
        folder.work_dir().join(TELEMETRY_CSV),
        board::record::CSV_HEADER.join(",") + "\n",
    )
    .unwrap();
    let mut m = meta(Vec::new());
    m.outcome = outcome;
    folder.publish(&mut m).unwrap()
}

#[test]
fn a_trial_written_before_lost_records_and_the_platform_id_still_reads() {
    let dir = tempfile::tempdir().unwrap();
    let path = publish(dir.path(), None, Outcome::Complete);
    // The trial.json of a writer that had neither field: the same object without their keys.
    let json = path.join("trial.json");
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let lost = v.as_object_mut().unwrap().remove("lost_records");
    let id = v["perturbation"]
        .as_object_mut()
        .unwrap()
        .remove("platform_id");
    assert_eq!((lost, id), (Some(0.into()), Some(23.into())));
    std::fs::write(&json, v.to_string()).unwrap();
    let t = read_trial(&path).unwrap();
    assert_eq!(t.meta.lost_records, None);
    let p = t.meta.perturbation.unwrap();
    assert_eq!(
        (p.leg.as_str(), p.moved_to, p.platform_id),
        ("RM", 2330, None)
    );
}

#[test]
fn two_trials_in_one_second_never_share_a_folder() {
    let dir = tempfile::tempdir().unwrap();
    let a = publish(dir.path(), None, Outcome::Complete);
    let b = publish(dir.path(), None, Outcome::Complete);
    // An interrupted one takes the next free name too, and says how it ended.
    let c = publish(dir.path(), None, Outcome::Interrupted);
    let names: Vec<_> = [&a, &b, &c]
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        [
            "2026-12-02 06_30_05",
            "2026-12-02 06_30_05 (2)",
            "2026-12-02 06_30_05 (3) interrupted"
        ]
    );
    let listed: Vec<_> = list_trials(dir.path())
        .unwrap()
        .into_iter()
        .map(|e| (e.folder, e.outcome))
        .collect();
    assert_eq!(
        listed,
        [
            (names[0].clone(), Outcome::Complete),
            (names[1].clone(), Outcome::Complete),
            (names[2].clone(), Outcome::Interrupted)
        ]
    );
    let index = std::fs::read_to_string(dir.path().join(INDEX_TXT)).unwrap();
    assert_eq!(index.lines().count(), 3);
    assert_eq!(read_trial(&c).unwrap().meta.outcome, Outcome::Interrupted);
}

#[test]
fn a_folder_that_exists_or_cannot_be_made_is_refused_before_anything_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let first = publish(dir.path(), Some("walk 1"), Outcome::Complete);
    let before = std::fs::read_to_string(dir.path().join(INDEX_TXT)).unwrap();
    // The same name again: refused, naming the folder; in any outcome's name as well.
    let e = TrialFolder::begin(dir.path(), Some("walk 1"), start()).unwrap_err();
    assert!(matches!(e, TrialError::Taken { .. }), "{e}");
    assert!(
        e.to_string().contains("walk 1") && e.to_string().contains("exists"),
        "{e}"
    );
    std::fs::create_dir(dir.path().join("walk 2 failed")).unwrap();
    let e = TrialFolder::begin(dir.path(), Some("walk 2"), start()).unwrap_err();
    assert!(matches!(e, TrialError::Taken { .. }), "{e}");
    // A name that is not one folder name.
    for bad in ["", ".hidden", "a/b"] {
        let e = TrialFolder::begin(dir.path(), Some(bad), start()).unwrap_err();
        assert!(matches!(e, TrialError::BadName { .. }), "{bad:?}: {e}");
    }
    // A folder of trials that is a file, or under a file (tests may run as root, for whom a
    // read-only folder is writable).
    let file = dir.path().join("notes.txt");
    std::fs::write(&file, "x").unwrap();
    let e = TrialFolder::begin(&file, None, start()).unwrap_err();
    assert!(matches!(e, TrialError::NotAFolder { .. }), "{e}");
    let e = TrialFolder::begin(&file.join("trials"), None, start()).unwrap_err();
    assert!(matches!(e, TrialError::Create { .. }), "{e}");
    assert!(e.to_string().contains("notes.txt"), "{e}");
    // Nothing changed: the first trial and the index are as they were, no folder was left.
    assert_eq!(read_trial(&first).unwrap().meta.folder, "walk 1");
    assert_eq!(
        std::fs::read_to_string(dir.path().join(INDEX_TXT)).unwrap(),
        before
    );
    let mut left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(
        left,
        [
            INDEX_TXT,
            "notes.txt",
            "trials.jsonl",
            "walk 1",
            "walk 2 failed"
        ]
    );
}

#[test]
fn a_trial_of_another_format_version_is_refused_naming_both() {
    let dir = tempfile::tempdir().unwrap();
    let p = publish(dir.path(), None, Outcome::Complete);
    let json = p.join("trial.json");
    let text = std::fs::read_to_string(&json).unwrap();
    std::fs::write(
        &json,
        text.replace("\"format_version\": 1", "\"format_version\": 7"),
    )
    .unwrap();
    let e = read_trial(&p).unwrap_err().to_string();
    assert!(
        e.contains("trial.json") && e.contains('7') && e.contains('1'),
        "{e}"
    );
}

use crate::gate;

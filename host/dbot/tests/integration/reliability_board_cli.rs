//! Host robustness of the board-facing `dbot` commands (issue #9), run as processes (the real
//! `CARGO_BIN_EXE_dbot`): a missing port, ports that are not a board (a regular file, a directory,
//! /dev/null, a pseudo-terminal nobody answers), a port without permission, a board of another
//! protocol version, and runs interrupted by Ctrl-C or killed. Each ends with a message naming the
//! port and the problem and a non-zero exit, within a bound; nothing but the version question is
//! sent to a board of another version; Ctrl-C leaves the robot standing; no output file is ever
//! half-written in place of a good one, and a killed upload leaves the stored gait intact.

use crate::board_fakes;
use std::os::fd::AsFd as _;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

use board_fakes::cli::{
    DEMO_FILES, HANG, fails_naming, run, spawn, spawn_with_env, strings, table, tree, wait_for,
    whole_csv_rows, whole_output, with_port,
};
use board_fakes::{Answer, FakeBoard, RobotServer, host_messages, pty};
use firmware::safety::State;
use firmware::testkit::SyntheticGait;
use nix::sys::signal::Signal;
use protocol::gait::FORMAT_VERSION;
use protocol::{HostMessage, PROTOCOL_VERSION, Request};

/// Every board-facing command with arguments that would work on a good board (`--port` is
/// appended by the caller). `devices` takes `--port` too, to ask a given port.
fn board_commands(dir: &Path, table: &str) -> Vec<Vec<String>> {
    let rec = dir.join("rec").display().to_string();
    [
        vec!["devices"],
        vec!["upload", "--table", table, "--slot", "1"],
        vec!["gaits"],
        vec!["run", "--slot", "0", "--steps", "1"],
        vec!["stop"],
        vec!["estop"],
        vec!["status"],
        vec!["servos"],
        vec!["set", "--stiffness", "5"],
        vec!["record", "--out", &rec, "--play", "0", "--steps", "1"],
    ]
    .iter()
    .map(|a| strings(a))
    .collect()
}

#[test]
fn every_board_command_on_a_missing_or_wrong_port_names_the_port_and_the_problem() {
    let dir = tempfile::tempdir().unwrap();
    let t = table(dir.path(), "g.dbgt", 20, 0.5);
    let file = dir.path().join("not-a-port");
    std::fs::write(&file, "x").unwrap();
    let folder = dir.path().join("a-folder");
    std::fs::create_dir(&folder).unwrap();
    let cases = [
        ("/dev/does-not-exist".to_owned(), "no such device"),
        (
            file.display().to_string(),
            "is a regular file, not a serial port",
        ),
        (
            folder.display().to_string(),
            "is a directory, not a serial port",
        ),
        ("/dev/null".to_owned(), "is not a serial port"),
    ];
    for (port, why) in &cases {
        for cmd in board_commands(dir.path(), &t) {
            let d = run(dir.path(), &with_port(&cmd, port));
            fails_naming(&d, &format!("{cmd:?} on {port}"), &[port, why]);
        }
    }
    // Nothing was recorded anywhere.
    assert!(!dir.path().join("rec").join("telemetry.csv").exists());
    assert_eq!(std::fs::read(&file).unwrap(), b"x");
}

#[test]
fn every_board_command_on_a_pty_nobody_answers_times_out_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let t = table(dir.path(), "g.dbgt", 20, 0.5);
    // One silent pseudo-terminal per command, all at once (each waits out its reply timeout).
    let cmds = board_commands(dir.path(), &t);
    let ptys: Vec<_> = cmds.iter().map(|_| pty()).collect();
    let runs: Vec<_> = cmds
        .iter()
        .zip(&ptys)
        .enumerate()
        .map(|(i, (c, p))| {
            spawn(
                dir.path(),
                &format!("silent{i}"),
                &with_port(c, &p.path),
                None,
            )
        })
        .collect();
    for ((run, cmd), p) in runs.into_iter().zip(&cmds).zip(&ptys) {
        let d = run.wait();
        fails_naming(
            &d,
            &format!("{cmd:?} on a silent pty"),
            &[&p.path, "no reply to GetDeviceInfo within"],
        );
    }
}

#[test]
fn a_port_without_permission_is_refused_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let t = table(dir.path(), "g.dbgt", 20, 0.5);
    // Root opens anything: run dbot as `nobody` then; as another user, as ourselves.
    // SAFETY: geteuid has no preconditions and cannot fail.
    let root = unsafe { nix::libc::geteuid() } == 0;
    let uid = root.then_some(65_534);
    if root {
        use std::os::unix::fs::PermissionsExt as _;
        for p in [dir.path(), Path::new(&t)] {
            std::fs::set_permissions(p, std::fs::Permissions::from_mode(0o755)).unwrap();
        }
        // `record` makes its output directory before it opens the port.
        let rec = dir.path().join("rec");
        std::fs::create_dir(&rec).unwrap();
        std::fs::set_permissions(&rec, std::fs::Permissions::from_mode(0o777)).unwrap();
        let probe = spawn(dir.path(), "probe", &strings(&["--version"]), uid).wait();
        if !probe.status.success() {
            eprintln!(
                "SKIPPED a_port_without_permission_is_refused_naming_it: running as root and \
                 dbot cannot run as uid 65534 here ({})",
                probe.stderr
            );
            return;
        }
    }
    // A board's port (a terminal) whose mode lets nobody in: /dev/ttyACM0 without `dialout`.
    let p = pty();
    nix::sys::stat::fchmod(p.slave.as_fd(), nix::sys::stat::Mode::empty()).unwrap();
    for cmd in board_commands(dir.path(), &t) {
        let d = spawn(dir.path(), "perm", &with_port(&cmd, &p.path), uid).wait();
        fails_naming(
            &d,
            &format!("{cmd:?} on a mode-000 terminal"),
            &[&p.path, "permission denied"],
        );
    }
}

#[test]
fn a_board_of_another_protocol_version_is_told_apart_and_sent_nothing_else() {
    let dir = tempfile::tempdir().unwrap();
    let t = table(dir.path(), "g.dbgt", 20, 0.5);
    let newer = PROTOCOL_VERSION + 1;
    let older = PROTOCOL_VERSION - 1;
    let cases = [
        (Answer::Version(newer), newer, "update dbot"),
        (Answer::Version(older), older, "update the firmware"),
        // A later version whose DeviceInfo gained fields: the reply does not decode here as a
        // whole, yet the versions at its start are read and named (not a 2 s "no reply").
        (Answer::VersionWithNewFields(newer), newer, "update dbot"),
        // Same protocol, a gait table format this dbot does not write.
        (
            Answer::TableFormat(FORMAT_VERSION + 1),
            FORMAT_VERSION + 1,
            "update dbot",
        ),
    ];
    for (answer, version, update) in cases {
        let (host, said) = match answer {
            Answer::TableFormat(_) => (
                format!("this dbot writes {FORMAT_VERSION}"),
                format!("gait table format {version}"),
            ),
            _ => (
                format!("this dbot speaks {PROTOCOL_VERSION}"),
                format!("protocol version {version}"),
            ),
        };
        for cmd in board_commands(dir.path(), &t) {
            let board = FakeBoard::start(answer);
            let port = board.pty_path.clone();
            let d = run(dir.path(), &with_port(&cmd, &port));
            let received = board.finish();
            let what = format!("{cmd:?} on a board of protocol {version} ({answer:?})");
            fails_naming(&d, &what, &[&port, &said, &host, update]);
            // Only the version question reached the board: no upload, no play, no settings.
            let messages = host_messages(&received);
            assert!(!messages.is_empty(), "{what}: the board heard nothing");
            for m in &messages {
                assert!(
                    matches!(
                        m,
                        Some(HostMessage::Request {
                            request: Request::GetDeviceInfo,
                            ..
                        })
                    ),
                    "{what}: the board also received {m:?}"
                );
            }
        }
    }
}

#[test]
fn ctrl_c_while_walking_on_a_board_leaves_it_standing_not_walking() {
    // The virtual robot served on a pty in real time stands for a board on USB: it lives on after
    // dbot exits, so what Ctrl-C left behind can be looked at.
    let dir = tempfile::tempdir().unwrap();
    let gait = SyntheticGait::new(40, 0.6).build();
    let (rec, rec2) = (dir.path().join("rec"), dir.path().join("rec2"));
    let record = |out: &Path, play: bool| {
        let mut a = strings(&["record", "--out", out.to_str().unwrap(), "--seconds", "600"]);
        if play {
            a.extend(strings(&["--play", "0"]));
        }
        a
    };
    // (started by another command first, the command, the signal once the robot is in this
    // state). Without --steps the gait plays until stopped. SIGTERM (a service manager, `kill`)
    // must end a walk as cleanly as Ctrl-C's SIGINT.
    let cases = [
        (
            None,
            strings(&["run", "--slot", "0"]),
            State::Walking,
            Signal::SIGINT,
        ),
        (
            None,
            strings(&["run", "--slot", "0"]),
            State::Ramping,
            Signal::SIGINT,
        ),
        (
            None,
            strings(&["run", "--slot", "0"]),
            State::Walking,
            Signal::SIGTERM,
        ),
        (None, record(&rec, true), State::Walking, Signal::SIGINT),
        (None, record(&rec, true), State::Walking, Signal::SIGTERM),
        // Recording a walk someone else started: Ctrl-C stops it all the same.
        (
            Some(strings(&[
                "run", "--slot", "0", "--steps", "1000", "--detach",
            ])),
            record(&rec2, false),
            State::Walking,
            Signal::SIGINT,
        ),
    ];
    for (first, cmd, when, signal) in cases {
        let what = format!("{cmd:?}, {signal} while {when:?}");
        let robot = RobotServer::start(gait.clone());
        if let Some(first) = first {
            let d = run(dir.path(), &with_port(&first, &robot.pty_path));
            assert!(d.status.success(), "{first:?}: {}", d.stderr);
        }
        let r = spawn(dir.path(), "walk", &with_port(&cmd, &robot.pty_path), None);
        wait_for(&what, HANG, || robot.state() == when);
        if cmd[0] == "record" {
            // Once rows arrive in the trial being recorded, the recording is under way.
            let trials = dir.path().join(&cmd[2]);
            wait_for(&what, HANG, || {
                std::fs::metadata(recording_csv(&trials)).is_ok_and(|m| m.len() > 1000)
            });
        }
        r.signal(signal);
        let d = r.wait();
        fails_naming(&d, &what, &["interrupted", "Standing"]);
        // What dbot says it stopped: the walk at the end of its step, or (when the stop came
        // during the ramp, which the ramp case usually catches) the ramp where it got to.
        let ramp = "the ramp to the gait's first slice was stopped where it got to";
        let step = "stopped at the end of its step";
        match when {
            State::Ramping => assert!(
                d.stderr.contains(ramp) || d.stderr.contains(step),
                "{what}: {}",
                d.stderr
            ),
            _ => assert!(d.stderr.contains(step), "{what}: {}", d.stderr),
        }
        // dbot only returned once the robot stood, and it stays standing.
        assert_eq!(robot.state(), State::Standing, "{what}: {}", d.stderr);
        std::thread::sleep(Duration::from_millis(300));
        assert_eq!(robot.state(), State::Standing, "{what}");
        robot.finish();
    }
    // Ctrl-C twice in a row (here SIGINT then SIGTERM, handled alike): dbot exits at once (130),
    // but only after asking the board to stop, so the robot still stands at the end of its step.
    let robot = RobotServer::start(gait.clone());
    let cmd = with_port(&strings(&["run", "--slot", "0"]), &robot.pty_path);
    let r = spawn(dir.path(), "twice", &cmd, None);
    wait_for("run: walking", HANG, || robot.state() == State::Walking);
    // Two different signals, both counted, so that they are not merged into one on delivery.
    r.signal(Signal::SIGINT);
    r.signal(Signal::SIGTERM);
    let d = r.wait();
    assert_eq!(d.status.code(), Some(130), "{}", d.stderr);
    assert!(d.stderr.contains("interrupted twice"), "{}", d.stderr);
    wait_for(
        "standing after Ctrl-C twice",
        Duration::from_secs(20),
        || robot.state() == State::Standing,
    );
    std::thread::sleep(Duration::from_millis(300));
    assert_eq!(robot.state(), State::Standing);
    robot.finish();
    // An endless run needs its host: `--detach` without `--steps` is refused, and nothing moves.
    let robot = RobotServer::start(gait.clone());
    let cmd = with_port(
        &strings(&["run", "--slot", "0", "--detach"]),
        &robot.pty_path,
    );
    let d = run(dir.path(), &cmd);
    assert!(!d.status.success());
    assert!(
        d.stderr.contains("--detach needs --steps K"),
        "{}",
        d.stderr
    );
    std::thread::sleep(Duration::from_millis(300));
    assert_ne!(robot.state(), State::Walking);
    robot.finish();
    // The interrupted recordings are kept, whole, as trials named so; none is left unfinished.
    for r in [&rec, &rec2] {
        let trial = board::trial::latest_trial(r).unwrap().unwrap();
        assert!(
            trial.to_string_lossy().ends_with(" interrupted"),
            "{}",
            trial.display()
        );
        assert!(whole_csv_rows(&trial.join("telemetry.csv")) > 0);
        assert!(trial.join("angles.png").exists());
        assert!(!recording_csv(r).exists());
    }
}

/// The telemetry CSV of the trial being recorded in the folder of trials `trials` (a hidden
/// `.partial-` folder until the recording ends); a path that does not exist when there is none.
fn recording_csv(trials: &Path) -> std::path::PathBuf {
    std::fs::read_dir(trials)
        .into_iter()
        .flatten()
        .map(|e| e.unwrap().path())
        .find(|p| {
            p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with(".partial-")
        })
        .unwrap_or_else(|| trials.join(".partial-none"))
        .join("telemetry.csv")
}

/// The `gaits` line of slot 1 of the virtual robot whose flash is `image`.
fn slot1(dir: &Path, image: &str) -> String {
    let d = run(dir, &strings(&["gaits", "--port", image]));
    assert!(d.status.success(), "gaits: {}", d.stderr);
    d.stdout
        .lines()
        .find(|l| l.starts_with("slot 1:"))
        .unwrap()
        .to_owned()
}

#[test]
fn an_upload_interrupted_or_killed_midway_leaves_the_stored_gait_intact() {
    let dir = tempfile::tempdir().unwrap();
    let image = format!("virtual:{}", dir.path().join("robot.flash").display());
    let old = table(dir.path(), "old.dbgt", 50, 1.0);
    // A large table (about 90 KB in 177 chunks).
    let new = table(dir.path(), "new.dbgt", 1000, 2.0);
    let up = |t: &str| {
        strings(&[
            "upload", "--table", t, "--slot", "1", "--port", &image, "--create",
        ])
    };
    let d = run(dir.path(), &up(&new));
    assert!(d.status.success(), "{}", d.stderr);
    let chunks: u32 = d
        .stdout
        .split(" chunks")
        .next()
        .and_then(|s| s.rsplit(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("the upload's chunk count: {}", d.stdout));
    assert!(chunks > 100, "{chunks} chunks");
    let new_line = slot1(dir.path(), &image);
    assert!(run(dir.path(), &up(&old)).status.success());
    let old_line = slot1(dir.path(), &image);
    assert_ne!(old_line, new_line);

    // One upload of the new table over the old one, held after chunk `k` (the CLI's test hook
    // DBOT_TEST_HOLD_AFTER_CHUNK: it waits there for a signal, so the signal lands mid-upload
    // whatever the machine's load), then `sig`. The slot must still hold the old gait, whole.
    let round = |sig: Signal, k: u32| {
        let held = format!("held after chunk {k}");
        let k_text = k.to_string();
        let env = [("DBOT_TEST_HOLD_AFTER_CHUNK", k_text.as_str())];
        let r = spawn_with_env(dir.path(), "upload", &up(&new), None, &env);
        while !std::fs::read_to_string(&r.err)
            .unwrap_or_default()
            .contains(&held)
        {
            assert!(
                r.started.elapsed() < HANG,
                "the upload never held at chunk {k}"
            );
            std::thread::sleep(Duration::from_millis(5));
        }
        r.signal(sig);
        let d = r.wait();
        assert_eq!(
            slot1(dir.path(), &image),
            old_line,
            "{sig:?} after chunk {k} of {chunks}: {}",
            d.stderr
        );
        if sig == Signal::SIGINT {
            // Ctrl-C before the commit: aborted, said so, naming how far it got.
            assert_eq!(d.status.code(), Some(1), "{}", d.stderr);
            fails_naming(
                &d,
                "upload after Ctrl-C",
                &["interrupted", "the slot keeps its previous table"],
            );
            assert!(!d.stderr.contains("after 0 of"), "{}", d.stderr);
        } else {
            assert_eq!(d.status.code(), None, "ended by the signal: {}", d.stderr);
        }
    };
    // Ctrl-C and SIGKILL after the first chunk, midway, before the last one, and after the last
    // one (before the commit).
    for k in [1, chunks / 2, chunks - 1, chunks] {
        round(Signal::SIGINT, k);
        round(Signal::SIGKILL, k);
    }
}

#[test]
fn a_recording_killed_leaves_whole_files() {
    let dir = tempfile::tempdir().unwrap();
    let image = format!("virtual:{}", dir.path().join("robot.flash").display());
    // 0.6 s: an MX-28 follows it (4.17 rad/s), as a table file must.
    let t = table(dir.path(), "g.dbgt", 40, 0.6);
    let d = run(
        dir.path(),
        &strings(&["upload", "--table", &t, "--port", &image, "--create"]),
    );
    assert!(d.status.success(), "{}", d.stderr);
    let rec = dir.path().join("rec");
    // Without --table only angles.png is drawn: drawing (PNG encoding in a debug build) is most
    // of a run on the virtual robot, whose walk runs on simulated time.
    let record = |out: &Path, backward: bool| {
        let mut a = strings(&["record", "--out", out.to_str().unwrap(), "--play", "0"]);
        a.extend(strings(&["--steps", "1", "--every", "4", "--port", &image]));
        if backward {
            a.push("--backward".into());
        }
        a
    };
    // The previous good recording (a trial folder in `rec`).
    let d = run(dir.path(), &record(&rec, false));
    assert!(d.status.success(), "{}", d.stderr);
    let took = d.took;
    let good = tree(&rec);
    assert_eq!(
        good.len(),
        6,
        "TRIAL INDEX.txt, trials.jsonl and the trial's telemetry.csv, angles.png, README.md, \
         trial.json: {:?}",
        good.iter().map(|(n, _)| n).collect::<Vec<_>>()
    );
    // SIGKILL (no chance to clean up) at moments spread over a run. Ctrl-C during a recording
    // is checked on a board in real time (ctrl_c_while_walking_...) and in the demo.
    for k in 1..=4u32 {
        let r = spawn(dir.path(), "record", &record(&rec, true), None);
        std::thread::sleep(took * k / 5);
        r.signal(Signal::SIGKILL);
        r.wait();
        let now: std::collections::BTreeMap<_, _> = tree(&rec).into_iter().collect();
        for (name, bytes) in &good {
            let kept = &now[name];
            // The earlier trial is untouched; the indexes only grow, by whole lines.
            if name.contains(std::path::MAIN_SEPARATOR) {
                assert_eq!(kept, bytes, "killed at {k}/5 of {took:?}: {name} changed");
            } else {
                assert!(kept.starts_with(bytes) && kept.ends_with(b"\n"), "{name}");
            }
        }
        // A trial killed before it ended stays a hidden `.partial-` folder: every published
        // trial's files are whole.
        for (name, bytes) in &now {
            let file = name.rsplit(std::path::MAIN_SEPARATOR).next().unwrap();
            if name.starts_with(".partial-") || !name.contains(std::path::MAIN_SEPARATOR) {
                continue;
            }
            assert!(
                whole_output(file, bytes),
                "killed at {k}/5 of {took:?}: {name} is not whole ({} bytes)",
                bytes.len()
            );
        }
    }
}

#[test]
fn a_demo_interrupted_while_recording_leaves_every_file_whole() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("demo");
    // The previous run's outputs (stand-ins with known bytes).
    let names = DEMO_FILES;
    let previous = |name: &str| format!("previous {name}\n").into_bytes();
    for n in names {
        let p = out.join(n);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(&p, previous(n)).unwrap();
    }
    let r = spawn(
        dir.path(),
        "demo",
        &strings(&["demo", "--steps", "1", "--out", out.to_str().unwrap()]),
        None,
    );
    // Ctrl-C once the second walk has started: the plan, the table and the first recording are
    // complete new files by then, the second recording is under way.
    wait_for("the demo's backward walk", HANG, || {
        std::fs::read_to_string(&r.out).is_ok_and(|s| s.contains("[5/7]"))
    });
    r.signal(Signal::SIGINT);
    let d = r.wait();
    fails_naming(
        &d,
        "demo after Ctrl-C",
        &["interrupted while recording", "backward"],
    );
    let files = tree(&out);
    for (name, bytes) in &files {
        assert!(!name.contains(".partial-"), "scratch file left: {name}");
        let old = *bytes == previous(name);
        let fresh = whole_output(name, bytes);
        assert!(
            old || fresh,
            "{name}: neither the previous file nor a whole new one"
        );
        // What was written before the Ctrl-C is new; the interrupted recording is the old one.
        assert_eq!(old, name.starts_with("record/backward"), "{name}");
    }
    assert_eq!(
        files.len(),
        names.len(),
        "{:?}",
        files.iter().map(|(n, _)| n).collect::<Vec<_>>()
    );
}

#[test]
fn missing_or_bad_input_files_are_named_with_the_place() {
    let dir = tempfile::tempdir().unwrap();
    let p = |n: &str| dir.path().join(n).display().to_string();
    let good = table(dir.path(), "good.dbgt", 20, 0.5);
    std::fs::write(p("short.dbgt"), b"garbage\n").unwrap();
    let mut bytes = std::fs::read(&good).unwrap();
    let last = bytes.len() - 1;
    bytes[last] ^= 0xFF;
    std::fs::write(p("crc.dbgt"), bytes).unwrap();
    std::fs::create_dir(p("plan")).unwrap();
    std::fs::write(
        p("plan/plan.json"),
        "{\n  \"model\": \"drosophibot2\",\n  oops\n}\n",
    )
    .unwrap();
    std::fs::create_dir(p("plan2")).unwrap();
    std::fs::write(
        p("plan2/plan.json"),
        r#"{"model_source": "drosophibot2", "period_s": 1.25, "parameters": {"duty": 0.6}}"#,
    )
    .unwrap();
    std::fs::write(
        p("plan2/joints.csv"),
        "slice,leg,joint,angle_rad,torque_nm\nx,LF,ThC1,0.1,0.2\n",
    )
    .unwrap();
    std::fs::write(p("bad.toml"), "stiffness = 8.4\nwobble = 1\n").unwrap();
    let f_bad_toml = p("bad.toml");
    let f_cmp = p("cmp");
    let f_crc_dbgt = p("crc.dbgt");
    let f_gone = p("gone");
    let f_gone_dbgt = p("gone.dbgt");
    let f_gone_toml = p("gone.toml");
    let f_plan = p("plan");
    let f_plan2 = p("plan2");
    let f_rec = p("rec");
    let f_short_dbgt = p("short.dbgt");
    // The port does not exist: every failure below must come from the file, checked first.
    let nope = "/dev/does-not-exist";
    let cases: Vec<(Vec<&str>, Vec<String>)> = vec![
        (
            vec!["upload", "--table", &f_gone_dbgt],
            vec![p("gone.dbgt")],
        ),
        (
            vec!["upload", "--table", &f_short_dbgt],
            vec![p("short.dbgt"), "needs 40".into()],
        ),
        (
            vec!["upload", "--table", &f_crc_dbgt],
            vec![p("crc.dbgt"), "CRC".into()],
        ),
        (
            vec!["upload", "--plan", &f_plan],
            vec![p("plan/plan.json"), "line 3".into()],
        ),
        (vec!["upload", "--plan", &f_gone], vec![p("gone/plan.json")]),
        (
            vec!["servos", "--table", &f_short_dbgt],
            vec![p("short.dbgt"), "not a step table".into()],
        ),
        (
            vec!["record", "--out", &f_rec, "--table", &f_gone_dbgt],
            vec![p("gone.dbgt")],
        ),
        (
            vec!["set", "--stiffness", "5", "--config", &f_bad_toml],
            vec![p("bad.toml"), "line 2".into(), "wobble".into()],
        ),
        (
            vec!["set", "--stiffness", "5", "--config", &f_gone_toml],
            vec![p("gone.toml")],
        ),
        (vec!["set", "--stiffness=-1"], vec!["--stiffness -1".into()]),
        (vec!["set"], vec!["nothing to set".into()]),
    ];
    for (args, needles) in cases {
        let d = run(dir.path(), &with_port(&strings(&args), nope));
        let needles: Vec<&str> = needles.iter().map(String::as_str).collect();
        fails_naming(&d, &format!("{args:?}"), &needles);
        assert!(
            !d.stderr.contains(nope),
            "{args:?}: touched the port first: {}",
            d.stderr
        );
    }
    // The file commands (no port).
    let out = p("out.dbgt");
    let file_cases: Vec<(Vec<&str>, Vec<String>)> = vec![
        // A plan.json of no plan directory format version (damaged rows of a current one:
        // plan_dir_roundtrip.rs).
        (
            vec!["table", "--plan", &f_plan2, "--out", &out],
            vec![p("plan2/plan.json"), "format_version".into()],
        ),
        (
            vec!["table", "--plan", &f_gone, "--out", &out],
            vec![p("gone/plan.json")],
        ),
        (
            vec!["compare", &f_plan2, &f_gone, "--out", &f_cmp],
            vec![p("plan2/plan.json"), "format_version".into()],
        ),
        (
            vec!["compare", &f_gone, &f_plan2, "--out", &f_cmp],
            vec![p("gone/plan.json")],
        ),
        (
            vec!["compare", &f_plan, "--out", &f_cmp],
            vec!["two plan directories".into()],
        ),
    ];
    for (args, needles) in file_cases {
        let d = run(dir.path(), &strings(&args));
        let needles: Vec<&str> = needles.iter().map(String::as_str).collect();
        fails_naming(&d, &format!("{args:?}"), &needles);
    }
    assert!(!Path::new(&out).exists());
}

#[test]
fn a_reader_that_goes_away_ends_dbot_quietly_not_with_a_panic() {
    // `dbot gaits | head -0`: the pipe is closed before dbot prints.
    let dir = tempfile::tempdir().unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_dbot"))
        .args(["gaits", "--port", "virtual"])
        .current_dir(dir.path())
        .env("RUST_BACKTRACE", "0")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!err.contains("panicked"), "{err}");
    use std::os::unix::process::ExitStatusExt as _;
    assert_eq!(
        o.status.signal(),
        Some(Signal::SIGPIPE as i32),
        "{:?} {err}",
        o.status
    );
}

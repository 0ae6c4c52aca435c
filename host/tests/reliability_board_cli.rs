//! Host robustness of the board-facing `dbot` commands (issue #9), run as processes (the real
//! `CARGO_BIN_EXE_dbot`): a missing port, ports that are not a board (a regular file, a directory,
//! /dev/null, a pseudo-terminal nobody answers), a port without permission, a board of another
//! protocol version, and runs interrupted by Ctrl-C or killed. Each ends with a message naming the
//! port and the problem and a non-zero exit, within a bound; nothing but the version question is
//! sent to a board of another version; Ctrl-C leaves the robot standing; no output file is ever
//! half-written in place of a good one, and a killed upload leaves the stored gait intact.

mod board_fakes;

use std::os::fd::AsFd as _;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

use board_fakes::{Answer, FakeBoard, RobotServer, host_messages, pty};
use firmware::safety::State;
use firmware::testkit::SyntheticGait;
use nix::sys::signal::{Signal, kill};
use nix::unistd::Pid;
use protocol::{HostMessage, PROTOCOL_VERSION, Request};

/// Longest any single command may take here before it counts as hung. Generous: the machine is
/// shared and the binaries are debug builds.
const HANG: Duration = Duration::from_secs(60);

/// A `dbot` process whose output goes to files in `dir` (no pipe to fill, no deadlock).
struct Run {
    child: Child,
    out: PathBuf,
    err: PathBuf,
    started: Instant,
}

/// What a finished run printed.
struct Done {
    status: ExitStatus,
    stdout: String,
    stderr: String,
    took: Duration,
}

fn spawn(dir: &Path, tag: &str, args: &[String], uid: Option<u32>) -> Run {
    let out = dir.join(format!("{tag}.stdout"));
    let err = dir.join(format!("{tag}.stderr"));
    let mut c = Command::new(env!("CARGO_BIN_EXE_dbot"));
    c.args(args)
        .current_dir(dir)
        .env_remove("DBOT_CONFIG")
        .env("XDG_CONFIG_HOME", dir)
        .env("HOME", dir)
        .env("RUST_BACKTRACE", "0")
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&out).unwrap())
        .stderr(std::fs::File::create(&err).unwrap());
    if let Some(uid) = uid {
        use std::os::unix::process::CommandExt as _;
        c.uid(uid).gid(uid);
    }
    Run {
        child: c.spawn().unwrap(),
        out,
        err,
        started: Instant::now(),
    }
}

impl Run {
    /// Waits for the end, killing the process (and failing the test) if it hangs.
    fn wait(mut self) -> Done {
        loop {
            if let Some(status) = self.child.try_wait().unwrap() {
                return Done {
                    status,
                    stdout: std::fs::read_to_string(&self.out).unwrap_or_default(),
                    stderr: std::fs::read_to_string(&self.err).unwrap_or_default(),
                    took: self.started.elapsed(),
                };
            }
            if self.started.elapsed() > HANG {
                let _ = self.child.kill();
                panic!(
                    "hung for {HANG:?}: {}",
                    std::fs::read_to_string(&self.err).unwrap_or_default()
                );
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    fn signal(&self, sig: Signal) {
        let _ = kill(Pid::from_raw(self.child.id() as i32), sig);
    }
}

fn run(dir: &Path, args: &[String]) -> Done {
    spawn(dir, "run", args, None).wait()
}

fn strings(args: &[&str]) -> Vec<String> {
    args.iter().map(|s| s.to_string()).collect()
}

/// A failure (not a panic, not a signal) whose stderr names every one of `needles`.
fn fails_naming(d: &Done, what: &str, needles: &[&str]) {
    assert!(
        !d.status.success(),
        "{what}: succeeded\n{}{}",
        d.stdout,
        d.stderr
    );
    assert_eq!(d.status.code(), Some(1), "{what}: {:?}\n{}", d.status, d.stderr);
    assert!(!d.stderr.contains("panicked"), "{what}: panicked: {}", d.stderr);
    for n in needles {
        assert!(d.stderr.contains(n), "{what}: stderr does not name `{n}`: {}", d.stderr);
    }
}

/// A small step table (22 joints) in `dir`.
fn table(dir: &Path, name: &str, slices: usize, period_s: f64) -> String {
    let p = dir.join(name);
    std::fs::write(&p, SyntheticGait::new(slices, period_s).build()).unwrap();
    p.display().to_string()
}

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

fn with_port(cmd: &[String], port: &str) -> Vec<String> {
    let mut a = cmd.to_vec();
    a.extend(["--port".to_owned(), port.to_owned()]);
    a
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
        (file.display().to_string(), "is a regular file, not a serial port"),
        (folder.display().to_string(), "is a directory, not a serial port"),
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
        .map(|(i, (c, p))| spawn(dir.path(), &format!("silent{i}"), &with_port(c, &p.path), None))
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
    ];
    let host = format!("this dbot speaks {PROTOCOL_VERSION}");
    for (answer, version, update) in cases {
        for cmd in board_commands(dir.path(), &t) {
            let board = FakeBoard::start(answer);
            let port = board.pty_path.clone();
            let d = run(dir.path(), &with_port(&cmd, &port));
            let received = board.finish();
            let what = format!("{cmd:?} on a board of protocol {version} ({answer:?})");
            fails_naming(
                &d,
                &what,
                &[&port, &format!("protocol version {version}"), &host, update],
            );
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

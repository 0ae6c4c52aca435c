//! Running `dbot` as a process for the board-facing tests (output to files, a bound on how long
//! it may take, signals) and checking that its output files are whole.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

use firmware::testkit::SyntheticGait;
use nix::sys::signal::{Signal, kill};
use nix::unistd::Pid;

/// Longest any single command may take here before it counts as hung. Generous: the machine is
/// shared and the binaries are debug builds.
pub const HANG: Duration = Duration::from_secs(60);

/// A `dbot` process whose output goes to files in `dir` (no pipe to fill, no deadlock).
pub struct Run {
    pub child: Child,
    pub out: PathBuf,
    pub err: PathBuf,
    pub started: Instant,
}

/// What a finished run printed.
pub struct Done {
    pub status: ExitStatus,
    pub stdout: String,
    pub stderr: String,
    pub took: Duration,
}

pub fn spawn(dir: &Path, tag: &str, args: &[String], uid: Option<u32>) -> Run {
    spawn_with_env(dir, tag, args, uid, &[])
}

/// [`spawn`] with these environment variables set as well.
pub fn spawn_with_env(
    dir: &Path,
    tag: &str,
    args: &[String],
    uid: Option<u32>,
    env: &[(&str, &str)],
) -> Run {
    let out = dir.join(format!("{tag}.stdout"));
    let err = dir.join(format!("{tag}.stderr"));
    let mut c = Command::new(env!("CARGO_BIN_EXE_dbot"));
    c.args(args);
    // A `virtual:PATH` store must exist unless --create is given: these tests make their robots.
    if args.iter().any(|a| a.starts_with("virtual:")) && !args.iter().any(|a| a == "--create") {
        c.arg("--create");
    }
    c.current_dir(dir)
        .env_remove("DBOT_CONFIG")
        .env("XDG_CONFIG_HOME", dir)
        .env("HOME", dir)
        .env("RUST_BACKTRACE", "0")
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&out).unwrap())
        .stderr(std::fs::File::create(&err).unwrap())
        .envs(env.iter().copied());
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
    pub fn wait(mut self) -> Done {
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

    pub fn signal(&self, sig: Signal) {
        let _ = kill(Pid::from_raw(self.child.id() as i32), sig);
    }
}

pub fn run(dir: &Path, args: &[String]) -> Done {
    spawn(dir, "run", args, None).wait()
}

pub fn strings(args: &[&str]) -> Vec<String> {
    args.iter().map(|s| s.to_string()).collect()
}

/// `record --out OUT --table T --play 0 --port PORT EXTRA`: a recording of the gait in `t`
/// uploaded to slot 0 and played there.
pub fn record_args(out: &Path, t: &str, port: &str, extra: &[&str]) -> Vec<String> {
    let mut a = strings(&[
        "record",
        "--out",
        out.to_str().unwrap(),
        "--table",
        t,
        "--play",
        "0",
        "--port",
        port,
        // The synthetic gaits the tests walk are not all ones an MX-28 follows (40 slices in
        // 0.4 s: 6.26 rad/s): a table file meets the servo rule at every door.
        "--allow-infeasible",
    ]);
    a.extend(strings(extra));
    a
}

/// A failure (not a panic, not a signal) whose stderr names every one of `needles`.
pub fn fails_naming(d: &Done, what: &str, needles: &[&str]) {
    assert!(
        !d.status.success(),
        "{what}: succeeded\n{}{}",
        d.stdout,
        d.stderr
    );
    assert_eq!(
        d.status.code(),
        Some(1),
        "{what}: {:?}\n{}",
        d.status,
        d.stderr
    );
    assert!(
        !d.stderr.contains("panicked"),
        "{what}: panicked: {}",
        d.stderr
    );
    for n in needles {
        assert!(
            d.stderr.contains(n),
            "{what}: stderr does not name `{n}`: {}",
            d.stderr
        );
    }
}

/// A small step table (22 joints) in `dir`.
pub fn table(dir: &Path, name: &str, slices: usize, period_s: f64) -> String {
    let p = dir.join(name);
    std::fs::write(&p, SyntheticGait::new(slices, period_s).build()).unwrap();
    p.display().to_string()
}

/// Waits (bounded) until `cond` holds.
pub fn wait_for(what: &str, limit: Duration, mut cond: impl FnMut() -> bool) {
    let t0 = Instant::now();
    while !cond() {
        assert!(t0.elapsed() < limit, "{what}: not within {limit:?}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Rows of a telemetry CSV, checking that it is whole: the header, then complete rows of every
/// column (22 joints per bus cycle), the last one ended by a newline.
pub fn whole_csv_rows(path: &Path) -> usize {
    let text = std::fs::read_to_string(path).unwrap();
    assert!(text.ends_with('\n'), "{}: last row cut", path.display());
    let mut lines = text.lines();
    assert_eq!(lines.next().unwrap(), board::record::CSV_HEADER.join(","));
    let rows: Vec<_> = lines.collect();
    for r in &rows {
        assert_eq!(
            r.split(',').count(),
            board::record::CSV_HEADER.len(),
            "{}: {r}",
            path.display()
        );
    }
    assert_eq!(
        rows.len() % 22,
        0,
        "{}: {} rows",
        path.display(),
        rows.len()
    );
    rows.len()
}

/// Every regular file in `dir` that is not a command's scratch file (`.partial-*`), with its bytes.
pub fn outputs(dir: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap())
        .filter(|e| e.file_type().unwrap().is_file())
        .map(|e| (e.file_name().to_string_lossy().into_owned(), e.path()))
        .filter(|(n, _)| !n.starts_with('.'))
        .map(|(n, p)| (n, std::fs::read(p).unwrap()))
        .collect()
}

/// Whether `bytes` are a whole PNG: the signature, and the IEND chunk (with its CRC) at the end.
pub fn whole_png(bytes: &[u8]) -> bool {
    const IEND: [u8; 12] = [0, 0, 0, 0, b'I', b'E', b'N', b'D', 0xAE, 0x42, 0x60, 0x82];
    bytes.starts_with(b"\x89PNG\r\n\x1a\n") && bytes.ends_with(&IEND)
}

/// Every file under `dir` (relative path, bytes), scratch files included.
pub fn tree(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                todo.push(p);
            } else {
                let rel = p.strip_prefix(dir).unwrap().display().to_string();
                out.push((rel, std::fs::read(&p).unwrap()));
            }
        }
    }
    out.sort();
    out
}

/// Whether `bytes` are a whole output of the kind its name says (checked by structure: a PNG ends
/// with IEND, a CSV has equal rows and a final newline, JSON parses, a table parses and its CRC
/// holds, a URDF closes its root element).
pub fn whole_output(name: &str, bytes: &[u8]) -> bool {
    let text = || std::str::from_utf8(bytes).ok();
    match name.rsplit('.').next() {
        Some("png") => whole_png(bytes),
        Some("csv") => text().is_some_and(|t| {
            let widths: Vec<_> = t.lines().map(|l| l.split(',').count()).collect();
            t.ends_with('\n') && widths.len() > 1 && widths.iter().all(|&w| w == widths[0])
        }),
        Some("json") => serde_json::from_slice::<serde_json::Value>(bytes).is_ok(),
        Some("urdf") => text().is_some_and(|t| t.trim_end().ends_with("</robot>")),
        Some("toml") => text().is_some_and(|t| t.parse::<toml::Table>().is_ok()),
        Some("dbgt") => protocol::GaitTable::parse(bytes).is_ok(),
        // A GIF ends with its trailer byte; the READMEs and feasibility.md are whole when they
        // end with a newline (each is written in one piece through a scratch file).
        Some("gif") => bytes.starts_with(b"GIF89a") && bytes.ends_with(&[0x3B]),
        Some("md") => text().is_some_and(|t| t.ends_with('\n')),
        _ => false,
    }
}

pub fn with_port(cmd: &[String], port: &str) -> Vec<String> {
    let mut a = cmd.to_vec();
    a.extend(["--port".to_owned(), port.to_owned()]);
    a
}

/// Every file `dbot demo --out OUT` writes into OUT (its plan, its step table, its two
/// recordings), and nothing else.
pub const DEMO_FILES: [&str; 24] = [
    "plan/joints.csv",
    "plan/feet.csv",
    "plan/plan.json",
    "plan/model.urdf",
    "plan/model.toml",
    "plan/joint_angles.png",
    "plan/footfall.png",
    "plan/feet.png",
    "plan/joint_forces.csv",
    "plan/torques.png",
    "plan/grf.png",
    "plan/robot.png",
    "plan/step.gif",
    "plan/feasibility.md",
    "plan/README.md",
    "plan/strain.csv",
    "plan/strain.png",
    "drosophibot2-tripod.dbgt",
    "record/forward/telemetry.csv",
    "record/forward/torque.png",
    "record/forward/angles.png",
    "record/backward/telemetry.csv",
    "record/backward/torque.png",
    "record/backward/angles.png",
];

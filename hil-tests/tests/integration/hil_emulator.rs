//! `hil-emulator` as a program: it prints `PORT /dev/pts/N` once the board's USB is up, the board
//! answers on that port (a fresh flash: idle, torque off), and it stops cleanly both when its stdin
//! closes and on SIGTERM: exit status 0, and every process it started (the Node runner, the servo
//! chain, defmt-print) is gone.

use anyhow::{Context, Result, bail, ensure};
use hil_tests::Options;
use hil_tests::link::Link;
use nix::sys::signal::{Signal, kill};
use nix::unistd::Pid;
use protocol::{Request, RunState, Status};
use std::io::{BufRead, BufReader};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

const HIL_EMULATOR: &str = env!("CARGO_BIN_EXE_hil-emulator");

/// How the test asks the program to stop.
#[derive(Debug, Clone, Copy)]
enum Stop {
    CloseStdin,
    Sigterm,
}

#[test]
fn serves_the_board_on_its_pty_and_stops_cleanly_on_eof_and_sigterm() -> Result<()> {
    let test = "hil_emulator";
    if let Some(why) = hil_tests::target::emulator_missing(&Options::default()) {
        return hil_tests::target::missing(test, &why);
    }
    if std::env::var_os("DBOT_HIL_PORT").is_some() {
        return hil_tests::target::skip(test, "hil-emulator is the emulator, not a real board");
    }
    for stop in [Stop::CloseStdin, Stop::Sigterm] {
        run_once(stop).with_context(|| format!("stopping with {stop:?}"))?;
    }
    Ok(())
}

fn run_once(stop: Stop) -> Result<()> {
    let mut child = Command::new(HIL_EMULATOR)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .context("cannot start hil-emulator")?;
    let stdout = child.stdout.take().context("stdout")?;
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let mut lines = BufReader::new(stdout).lines();
        let _ = tx.send(lines.next());
        // Anything more on stdout breaks the one-line contract.
        let _ = tx.send(lines.next());
    });
    let first = rx
        .recv_timeout(Duration::from_secs(60))
        .context("no line from hil-emulator within 60 s")?
        .context("hil-emulator closed stdout without a line")??;
    let port = PathBuf::from(
        first
            .strip_prefix("PORT ")
            .with_context(|| format!("first line is not `PORT <path>`: {first:?}"))?,
    );
    let started = descendants(child.id());
    ensure!(
        started.len() >= 3,
        "expected the runner, the servo chain and defmt-print under hil-emulator, found {started:?}"
    );

    let mut link = Link::open(&port)?;
    let status: Status = link.request(&Request::GetStatus, Duration::from_secs(10))?;
    ensure!(
        status.state == RunState::Idle && status.torque_enabled == 0,
        "a board with an erased flash should be idle with torque off: {status:?}"
    );
    drop(link);

    match stop {
        Stop::CloseStdin => drop(child.stdin.take()),
        Stop::Sigterm => kill(Pid::from_raw(child.id() as i32), Signal::SIGTERM)?,
    }
    let code = wait_exit(&mut child, Duration::from_secs(15))?;
    ensure!(code == Some(0), "hil-emulator exited with {code:?}");
    if let Ok(Some(Ok(extra))) = rx.recv_timeout(Duration::from_secs(5)) {
        bail!("a second line on stdout: {extra:?}");
    }
    let deadline = Instant::now() + Duration::from_secs(5);
    loop {
        let alive: Vec<u32> = started.iter().copied().filter(|&p| running(p)).collect();
        if alive.is_empty() {
            return Ok(());
        }
        ensure!(
            Instant::now() < deadline,
            "processes left behind after hil-emulator exited: {alive:?}"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
}

fn wait_exit(child: &mut Child, limit: Duration) -> Result<Option<i32>> {
    let deadline = Instant::now() + limit;
    while Instant::now() < deadline {
        if let Some(status) = child.try_wait()? {
            return Ok(status.code());
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let _ = child.kill();
    bail!("hil-emulator did not exit within {limit:?}")
}

/// Every process below `pid` (children, their children, ...), from /proc.
fn descendants(pid: u32) -> Vec<u32> {
    let parents: Vec<(u32, u32)> = std::fs::read_dir("/proc")
        .into_iter()
        .flatten()
        .flatten()
        .filter_map(|e| e.file_name().to_str()?.parse::<u32>().ok())
        .filter_map(|p| Some((p, parent(p)?)))
        .collect();
    let mut out = Vec::new();
    let mut frontier = vec![pid];
    while let Some(p) = frontier.pop() {
        for &(child, _) in parents.iter().filter(|(_, pp)| *pp == p) {
            out.push(child);
            frontier.push(child);
        }
    }
    out
}

/// The parent of `pid`: field 4 of /proc/PID/stat, after the parenthesised command name.
fn parent(pid: u32) -> Option<u32> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    let rest = &stat[stat.rfind(')')? + 2..];
    rest.split_whitespace().nth(1)?.parse().ok()
}

/// Whether `pid` exists and is not a zombie waiting for its parent.
fn running(pid: u32) -> bool {
    let Ok(stat) = std::fs::read_to_string(format!("/proc/{pid}/stat")) else {
        return false;
    };
    let state = stat
        .rfind(')')
        .and_then(|i| stat[i + 2..].split_whitespace().next());
    state != Some("Z")
}

//! The Rust side of the emulator runner (hil-tests/runner): starts `node runner/src/main.js` on the
//! firmware ELF, speaks its JSON-lines control channel, bridges the emulated USB CDC-ACM link to a
//! pty, and collects the decoded defmt log lines (also printed into the test output with the
//! simulated time, so a failing test shows what the firmware said).

use crate::pty::PtyBridge;
use anyhow::{Context, Result, anyhow, bail};
use serde_json::{Value, json};
use std::collections::HashMap;
use std::io::{BufRead, BufReader, Write};
use std::os::unix::net::UnixListener;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

/// How to start the emulator.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// The firmware ELF (defaults to [`crate::paths::firmware_elf`]).
    pub elf: Option<PathBuf>,
    /// Flash persistence file (2 MB); created on first save, reused when present.
    pub flash_file: Option<PathBuf>,
    /// argv of the virtual servo chain process on the bus UART (see runner/src/bus.js).
    pub bus: Option<Vec<String>>,
    /// Cap simulated time at this multiple of wall time (None: as fast as possible).
    pub realtime: Option<f64>,
    /// Processes whose threads must all be blocked for simulated time to pass (runner/src/pace.js):
    /// the host and whatever carries its bytes, so a host slowed by a loaded machine does not
    /// fall behind the board. Empty: simulated time runs freely.
    pub paced_by: Vec<u32>,
    /// Where decoded defmt lines and runner notices are echoed (they are collected either way).
    pub echo: Echo,
}

/// Where the harness echoes the firmware's log lines and the runner's notices.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Echo {
    /// Standard output: captured by the test harness, shown for failing tests.
    #[default]
    Stdout,
    /// Standard error (a program whose stdout carries data, e.g. `hil-emulator`).
    Stderr,
    /// Not echoed.
    Off,
}

/// What the USB OUT trace records (host to board), in simulated time.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum UsbOut {
    /// `len` bytes written by the host (to the pty) reached the runner; the chip takes them in
    /// packets once its firmware has armed the OUT endpoint.
    FromHost { at: Duration, len: usize },
    /// A packet (at most 64 bytes, one full-speed bulk packet) landed in the chip's endpoint
    /// buffer.
    ToChip { at: Duration, data: Vec<u8> },
}

/// A bus burst with the bytes the board put on the wire.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TracedBurst {
    pub burst: BusBurst,
    pub bytes: Vec<u8>,
}

/// One transmission of the board on the bus, as the runner saw it on the wire.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BusBurst {
    /// Simulated time of the first start bit.
    pub start: Duration,
    /// Simulated time the last stop bit ended: the line is idle from here until the next burst
    /// (a burst ends only when the UART's FIFO and shift register are empty).
    pub end: Duration,
    /// Bytes in the burst.
    pub len: usize,
    /// Instruction byte when the burst starts with a Protocol 2.0 header.
    pub instruction: Option<u8>,
    /// When the servos' answer to this burst ended on the wire (None: no answer).
    pub answer_end: Option<Duration>,
}

/// One decoded defmt line.
#[derive(Debug, Clone, PartialEq)]
pub struct LogLine {
    /// Simulated time when the runner read it from RTT.
    pub sim: Duration,
    /// The line as defmt-print printed it (includes the firmware's own timestamp).
    pub text: String,
}

#[derive(Debug, Default)]
struct State {
    logs: Vec<LogLine>,
    replies: HashMap<u64, Value>,
    events: Vec<Value>,
    closed: Option<String>,
}

#[derive(Debug, Default)]
struct Shared {
    state: Mutex<State>,
    changed: Condvar,
}

/// A running emulated board. Dropping it stops the runner.
#[derive(Debug)]
pub struct Emulator {
    child: Child,
    stdin: Mutex<ChildStdin>,
    shared: Arc<Shared>,
    pty: PtyBridge,
    next_id: AtomicU64,
    _dir: tempfile::TempDir,
}

/// Wall-clock bound on any single wait, so a wedged runner fails a test instead of hanging CI.
const WALL_LIMIT: Duration = Duration::from_secs(120);

impl Emulator {
    /// Starts the runner and waits until it reports `ready`.
    pub fn start(opts: Options) -> Result<Self> {
        let elf = opts.elf.unwrap_or_else(crate::paths::firmware_elf);
        let dir = tempfile::tempdir().context("cannot make a temp dir for the runner's socket")?;
        let sock_path = dir.path().join("usb.sock");
        let listener = UnixListener::bind(&sock_path)
            .with_context(|| format!("cannot listen on {}", sock_path.display()))?;
        let runner = crate::paths::runner_dir();
        let mut cmd = Command::new("node");
        // Extra node flags, e.g. `--cpu-prof --cpu-prof-dir=/tmp/prof` to profile the runner (node
        // refuses --cpu-prof in NODE_OPTIONS).
        if let Some(extra) = std::env::var_os("DBOT_HIL_NODE_ARGS") {
            cmd.args(extra.to_string_lossy().split_whitespace());
        }
        cmd.arg(runner.join("src/main.js"))
            .arg("--elf")
            .arg(&elf)
            .arg("--usb-socket")
            .arg(&sock_path)
            .current_dir(&runner)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit());
        if let Some(f) = &opts.flash_file {
            cmd.arg("--flash-file").arg(f);
        }
        if let Some(bus) = &opts.bus {
            cmd.arg("--bus-cmd").arg(serde_json::to_string(bus)?);
        }
        if let Some(r) = opts.realtime {
            cmd.arg("--realtime").arg(r.to_string());
        }
        if !opts.paced_by.is_empty() {
            let pids: Vec<String> = opts.paced_by.iter().map(u32::to_string).collect();
            cmd.arg("--paced-by").arg(pids.join(","));
        }
        if let Some(dp) = defmt_print() {
            cmd.arg("--defmt-print").arg(dp);
        }
        let mut child = cmd
            .spawn()
            .context("cannot start `node` (Node 20+ is needed for the emulator runner)")?;
        let stdin = child.stdin.take().context("runner stdin")?;
        let stdout = child.stdout.take().context("runner stdout")?;
        let shared = Arc::new(Shared::default());
        let reader_shared = shared.clone();
        let echo = opts.echo;
        std::thread::spawn(move || read_events(BufReader::new(stdout), &reader_shared, echo));

        listener.set_nonblocking(true)?;
        let started = Instant::now();
        let stream = loop {
            match listener.accept() {
                Ok((s, _)) => break s,
                Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {
                    if let Some(why) = shared.state.lock().unwrap().closed.clone() {
                        bail!("emulator runner stopped before connecting: {why}");
                    }
                    if started.elapsed() > Duration::from_secs(30) {
                        bail!("emulator runner did not connect its USB socket within 30 s");
                    }
                    std::thread::sleep(Duration::from_millis(10));
                }
                Err(e) => return Err(e).context("accept on the USB socket"),
            }
        };
        stream.set_nonblocking(false)?;
        let pty = PtyBridge::new(stream)?;
        let emu = Self {
            child,
            stdin: Mutex::new(stdin),
            shared,
            pty,
            next_id: AtomicU64::new(1),
            _dir: dir,
        };
        emu.wait_event("ready", Duration::from_secs(30))?;
        Ok(emu)
    }

    /// The pty path that stands for the board's USB serial port.
    pub fn port(&self) -> &Path {
        self.pty.path()
    }

    /// Sends a command and waits (wall clock) for its reply.
    pub fn command(&self, mut cmd: Value) -> Result<Value> {
        let id = self.next_id.fetch_add(1, Ordering::Relaxed);
        cmd["id"] = json!(id);
        let name = cmd["cmd"].as_str().unwrap_or("?").to_string();
        {
            let mut stdin = self.stdin.lock().unwrap();
            writeln!(stdin, "{cmd}").with_context(|| format!("sending `{name}` to the runner"))?;
            stdin.flush()?;
        }
        let reply = self.wait(WALL_LIMIT, |s| s.replies.remove(&id))?;
        if reply["ok"] != json!(true) {
            bail!("runner refused `{name}`: {}", reply["error"]);
        }
        Ok(reply)
    }

    /// Simulated time since the first boot.
    pub fn sim_time(&self) -> Result<Duration> {
        let r = self.command(json!({"cmd": "time"}))?;
        Ok(nanos(&r["sim_ns"]))
    }

    /// Lets `d` of simulated time pass and returns the simulated time then.
    pub fn run_for(&self, d: Duration) -> Result<Duration> {
        let target = self.sim_time()? + d;
        let r = self.command(json!({"cmd": "wait_until", "sim_ns": target.as_nanos() as u64}))?;
        Ok(nanos(&r["sim_ns"]))
    }

    /// Waits until a log line containing `needle` appears, at most `sim_timeout` of simulated time
    /// from now. Lines from before the call count too.
    pub fn wait_for_log(&self, needle: &str, sim_timeout: Duration) -> Result<LogLine> {
        let deadline = self.sim_time()? + sim_timeout;
        let started = Instant::now();
        loop {
            let logs = self.logs();
            if let Some(l) = logs.iter().find(|l| l.text.contains(needle)) {
                return Ok(l.clone());
            }
            if logs.iter().any(|l| l.text.contains("panicked at")) {
                bail!(
                    "the firmware panicked while waiting for {needle:?}:\n{}",
                    self.log_text()
                );
            }
            let now = self.sim_time()?;
            if now > deadline || started.elapsed() > WALL_LIMIT {
                bail!(
                    "no log line containing {needle:?} within {sim_timeout:?} of simulated time \
                     (now {now:?}); the firmware logged:\n{}",
                    self.log_text()
                );
            }
            let guard = self.shared.state.lock().unwrap();
            let _ = self
                .shared
                .changed
                .wait_timeout(guard, Duration::from_millis(50));
        }
    }

    /// All decoded log lines so far.
    pub fn logs(&self) -> Vec<LogLine> {
        self.shared.state.lock().unwrap().logs.clone()
    }

    fn log_text(&self) -> String {
        self.logs()
            .iter()
            .map(|l| format!("  [{:>10.6} s] {}", l.sim.as_secs_f64(), l.text))
            .collect::<Vec<_>>()
            .join("\n")
    }

    /// Events of one kind seen so far (`usb_configured`, `reset`, `halted`, `warn`, ...).
    pub fn events(&self, kind: &str) -> Vec<Value> {
        let state = self.shared.state.lock().unwrap();
        state
            .events
            .iter()
            .filter(|e| e["event"] == json!(kind))
            .cloned()
            .collect()
    }

    /// Waits (wall clock) for the `n`-th event of a kind and returns it.
    pub fn wait_event_n(&self, kind: &str, n: usize, wall: Duration) -> Result<Value> {
        let kind_v = json!(kind);
        self.wait(wall, |s| {
            s.events
                .iter()
                .filter(|e| e["event"] == kind_v)
                .nth(n.saturating_sub(1))
                .cloned()
        })
        .with_context(|| format!("waiting for event `{kind}` #{n}"))
    }

    fn wait_event(&self, kind: &str, wall: Duration) -> Result<Value> {
        self.wait_event_n(kind, 1, wall)
    }

    fn wait<T>(&self, wall: Duration, mut f: impl FnMut(&mut State) -> Option<T>) -> Result<T> {
        let started = Instant::now();
        let mut state = self.shared.state.lock().unwrap();
        loop {
            if let Some(v) = f(&mut state) {
                return Ok(v);
            }
            if let Some(why) = &state.closed {
                return Err(anyhow!("emulator runner stopped: {why}"));
            }
            if started.elapsed() > wall {
                bail!("timed out after {wall:?} (wall clock)");
            }
            state = self
                .shared
                .changed
                .wait_timeout(state, Duration::from_millis(100))
                .unwrap()
                .0;
        }
    }

    /// Resets the emulated chip now; flash contents are kept.
    pub fn reset(&self) -> Result<()> {
        self.command(json!({"cmd": "reset"})).map(drop)
    }

    /// Arms a reset right after the `nth` flash program operation from now; with `torn_bytes`,
    /// that operation writes only its first `torn_bytes` bytes (power lost mid-write).
    pub fn reset_on_flash_program(&self, nth: u32, torn_bytes: Option<u32>) -> Result<()> {
        let mut cmd = json!({"cmd": "reset_on_flash_program", "nth": nth});
        if let Some(t) = torn_bytes {
            cmd["torn_bytes"] = json!(t);
        }
        self.command(cmd).map(drop)
    }

    /// Unplugs and re-plugs the USB cable (bus reset, new enumeration).
    pub fn usb_replug(&self) -> Result<()> {
        self.command(json!({"cmd": "usb_replug"})).map(drop)
    }

    /// Bytes the host has sent that the board has not taken yet.
    pub fn usb_pending(&self) -> Result<u64> {
        Ok(self.command(json!({"cmd": "usb_pending"}))?["bytes"]
            .as_u64()
            .unwrap_or(0))
    }

    /// Runner counters: simulated and wall time, UART, USB, bus and flash statistics.
    pub fn stats(&self) -> Result<Value> {
        self.command(json!({"cmd": "stats"}))
    }

    /// Writes the flash contents to the flash file now.
    pub fn save_flash(&self) -> Result<()> {
        self.command(json!({"cmd": "save_flash"})).map(drop)
    }

    /// Stops the runner's recording `cmd` and returns its entries, the array `field` of the answer.
    fn stop_trace(&self, cmd: &str, field: &str) -> Result<Vec<Value>> {
        let mut r = self.command(json!({"cmd": cmd, "on": false}))?;
        Ok(match r.get_mut(field).map(Value::take) {
            Some(Value::Array(entries)) => entries,
            _ => Vec::new(),
        })
    }

    /// Starts recording the start times of bus bursts (board transmissions).
    pub fn bus_trace_start(&self) -> Result<()> {
        self.command(json!({"cmd": "bus_trace", "on": true}))
            .map(drop)
    }

    /// Stops recording and returns every burst the board transmitted since the start.
    pub fn bus_trace_stop(&self) -> Result<Vec<BusBurst>> {
        Ok(self
            .stop_trace("bus_trace", "bursts")?
            .iter()
            .map(burst)
            .collect())
    }

    /// Like [`Self::bus_trace_stop`], with the bytes of every burst (the recording must have been
    /// started with [`Self::bus_trace_start`]).
    pub fn bus_trace_stop_bytes(&self) -> Result<Vec<TracedBurst>> {
        self.stop_trace("bus_trace", "bursts")?
            .iter()
            .map(|b| {
                Ok(TracedBurst {
                    burst: burst(b),
                    bytes: hex(&b["tx"]).context("a bus trace entry without its bytes")?,
                })
            })
            .collect()
    }

    /// Sets the host's turnaround before each USB OUT packet lands on the chip (default 10 us,
    /// back to that after a reset). The host's bytes enter simulated time only between the
    /// runner's run slices, so sweeping this is how a test makes packets land at any phase.
    pub fn set_usb_out_delay(&self, d: Duration) -> Result<()> {
        self.command(json!({"cmd": "usb_out_delay", "ns": d.as_nanos() as u64}))
            .map(drop)
    }

    /// Starts recording the USB OUT packets handed to the chip (dropping any earlier recording).
    pub fn usb_trace_start(&self) -> Result<()> {
        self.command(json!({"cmd": "usb_trace", "on": true}))
            .map(drop)
    }

    /// Stops recording and returns what the USB OUT path saw since the start, oldest first.
    pub fn usb_trace_stop(&self) -> Result<Vec<UsbOut>> {
        self.stop_trace("usb_trace", "packets")?
            .iter()
            .map(|e| {
                let at = nanos(&e["sim_ns"]);
                Ok(match e["host_bytes"].as_u64() {
                    Some(len) => UsbOut::FromHost {
                        at,
                        len: len as usize,
                    },
                    None => UsbOut::ToChip {
                        at,
                        data: hex(&e["data"]).context("a USB trace entry without its bytes")?,
                    },
                })
            })
            .collect()
    }

    /// Sends a control message to the servo chain process (fault injection).
    pub fn bus_control(&self, msg: Value) -> Result<()> {
        self.command(json!({"cmd": "bus_control", "msg": msg}))
            .map(drop)
    }
}

impl Drop for Emulator {
    fn drop(&mut self) {
        if let Ok(mut stdin) = self.stdin.lock() {
            let _ = writeln!(stdin, "{}", json!({"cmd": "quit", "id": 0}));
        }
        let started = Instant::now();
        while started.elapsed() < Duration::from_secs(2) {
            if let Ok(Some(_)) = self.child.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn nanos(v: &Value) -> Duration {
    Duration::from_nanos(v.as_f64().unwrap_or(0.0) as u64)
}

fn burst(b: &Value) -> BusBurst {
    BusBurst {
        start: nanos(&b["start_ns"]),
        end: nanos(&b["end_ns"]),
        len: b["len"].as_u64().unwrap_or(0) as usize,
        instruction: b["inst"].as_u64().map(|i| i as u8),
        answer_end: b["rx_end_ns"]
            .as_f64()
            .map(|n| Duration::from_nanos(n as u64)),
    }
}

/// Bytes from the runner's hex strings.
fn hex(v: &Value) -> Result<Vec<u8>> {
    let s = v.as_str().context("no hex string")?;
    if s.len() % 2 != 0 {
        bail!("odd-length hex string from the runner: {s:?}");
    }
    (0..s.len())
        .step_by(2)
        .map(|i| {
            u8::from_str_radix(&s[i..i + 2], 16)
                .with_context(|| format!("not hex at {i}: {:?}", &s[i..i + 2]))
        })
        .collect()
}

fn read_events(stdout: BufReader<std::process::ChildStdout>, shared: &Shared, echo: Echo) {
    let say = |text: std::fmt::Arguments| match echo {
        Echo::Stdout => println!("{text}"),
        Echo::Stderr => eprintln!("{text}"),
        Echo::Off => {}
    };
    for line in stdout.lines() {
        let Ok(line) = line else { break };
        let Ok(v) = serde_json::from_str::<Value>(&line) else {
            say(format_args!("[runner] {line}"));
            continue;
        };
        let mut state = shared.state.lock().unwrap();
        if let Some(id) = v["id"].as_u64() {
            state.replies.insert(id, v);
        } else {
            match v["event"].as_str() {
                Some("log") => {
                    let l = LogLine {
                        sim: nanos(&v["sim_ns"]),
                        text: v["line"].as_str().unwrap_or("").to_string(),
                    };
                    say(format_args!("[{:>10.6} s] {}", l.sim.as_secs_f64(), l.text));
                    state.logs.push(l);
                }
                Some("warn") | Some("fatal") | Some("halted") | Some("reset") => {
                    say(format_args!("[runner] {v}"));
                    if v["event"] == json!("fatal") {
                        state.closed = Some(v["msg"].as_str().unwrap_or("fatal").to_string());
                    }
                    state.events.push(v);
                }
                _ => state.events.push(v),
            }
        }
        shared.changed.notify_all();
    }
    let mut state = shared.state.lock().unwrap();
    state.closed.get_or_insert_with(|| "runner exited".into());
    shared.changed.notify_all();
}

/// defmt-print: `DBOT_HIL_DEFMT_PRINT`, else on PATH, else in `$CARGO_HOME/bin` (~/.cargo/bin).
pub fn defmt_print() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("DBOT_HIL_DEFMT_PRINT") {
        return Some(PathBuf::from(p));
    }
    let on_path = std::env::var_os("PATH").and_then(|paths| {
        std::env::split_paths(&paths)
            .map(|d| d.join("defmt-print"))
            .find(|p| p.is_file())
    });
    on_path.or_else(|| {
        let home = std::env::var_os("CARGO_HOME")
            .map(PathBuf::from)
            .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cargo")))?;
        let p = home.join("bin/defmt-print");
        p.is_file().then_some(p)
    })
}

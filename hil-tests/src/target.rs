//! Which board a HIL test runs against: a real Drosophibot II when `DBOT_HIL_PORT` names its serial
//! port (flashed first with `probe-rs run` unless `DBOT_HIL_FLASH=0`), otherwise the emulator. When
//! neither is possible the test is skipped with a message written straight to stderr (so it shows
//! even under output capture); under CI (`CI` set) that is a failure instead, never a silent pass.

use crate::emulator::{Emulator, LogLine, Options};
use anyhow::{Context, Result, bail};
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// The board under test.
#[derive(Debug)]
pub enum Target {
    /// The firmware image in the RP2040 emulator.
    Emulator(Emulator),
    /// A real board on a serial port.
    Real(RealBoard),
}

/// A real board: its port and the defmt log lines `probe-rs run` streams.
#[derive(Debug)]
pub struct RealBoard {
    port: PathBuf,
    probe: Option<Child>,
    logs: Arc<Mutex<Vec<String>>>,
}

impl Target {
    /// Picks the target for `test` (its name, for the skip message). `Ok(None)` means skipped
    /// (message already printed).
    pub fn start(test: &str, opts: Options) -> Result<Option<Self>> {
        if let Some(port) = std::env::var_os("DBOT_HIL_PORT") {
            return RealBoard::start(PathBuf::from(port)).map(|b| Some(Self::Real(b)));
        }
        if let Some(why) = emulator_missing(&opts) {
            return missing(test, &why).map(|()| None);
        }
        Emulator::start(opts).map(|e| Some(Self::Emulator(e)))
    }

    /// The serial port to hand to `dbot --port` or to open directly.
    pub fn port(&self) -> &Path {
        match self {
            Self::Emulator(e) => e.port(),
            Self::Real(r) => &r.port,
        }
    }

    /// The emulator, for tests that need its controls (reset, fault injection, bus trace).
    pub fn emulator(&self) -> Option<&Emulator> {
        match self {
            Self::Emulator(e) => Some(e),
            Self::Real(_) => None,
        }
    }

    /// Lets `d` pass on the board: simulated time on the emulator (it runs that long), wall time
    /// on a real board.
    pub fn run_for(&self, d: Duration) -> Result<()> {
        match self {
            Self::Emulator(e) => e.run_for(d).map(drop),
            Self::Real(_) => {
                std::thread::sleep(d);
                Ok(())
            }
        }
    }

    /// Waits for a log line containing `needle`: `timeout` is simulated time on the emulator and
    /// wall time on a real board.
    pub fn wait_for_log(&self, needle: &str, timeout: Duration) -> Result<String> {
        match self {
            Self::Emulator(e) => e.wait_for_log(needle, timeout).map(|l: LogLine| l.text),
            Self::Real(r) => r.wait_for_log(needle, timeout),
        }
    }
}

/// Prints why a test does not apply to the real board named by `DBOT_HIL_PORT` (an opt-in run:
/// emulator-only tests cannot inject their faults there). Never used for a missing emulator:
/// that is [`missing`].
pub fn skip(test: &str, why: &str) -> Result<()> {
    let _ = writeln!(
        std::io::stderr().lock(),
        "SKIPPED {test} on the real board (DBOT_HIL_PORT): {why}"
    );
    Ok(())
}

/// Opt-out for a developer's machine without the emulator's prerequisites: `DBOT_HIL_OPTIONAL=1`
/// turns a missing prerequisite into a printed skip. The test command (scripts/test.sh) unsets it.
pub const OPTIONAL_ENV: &str = "DBOT_HIL_OPTIONAL";

/// A prerequisite of the emulator is missing: an error (the test command must run the emulator
/// tests or fail, issue #19), unless [`OPTIONAL_ENV`] is set.
pub fn missing(test: &str, why: &str) -> Result<()> {
    if std::env::var_os(OPTIONAL_ENV).is_none_or(|v| v.is_empty() || v == "0") {
        bail!(
            "{test}: cannot run on the emulated board: {why} (scripts/setup.d/30-hil.sh installs \
             the prerequisites; {OPTIONAL_ENV}=1 skips these tests instead)"
        );
    }
    let _ = writeln!(
        std::io::stderr().lock(),
        "SKIPPED {test} ({OPTIONAL_ENV} is set): {why}"
    );
    Ok(())
}

/// Why the emulator cannot run here, if it cannot (with the setup command that fixes it).
pub fn emulator_missing(opts: &Options) -> Option<String> {
    let elf = opts.elf.clone().unwrap_or_else(crate::paths::firmware_elf);
    if !elf.exists() {
        return Some(format!(
            "no firmware image at {} (build it with `(cd firmware && cargo build --release)`)",
            elf.display()
        ));
    }
    let ok = Command::new("node")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        return Some("`node` (Node 20+) is not installed".into());
    }
    let rp2040js = crate::paths::runner_dir().join("node_modules/rp2040js/package.json");
    if !rp2040js.exists() {
        return Some(format!(
            "{} is missing (run scripts/setup.d/30-hil.sh, i.e. `npm ci` in hil-tests/runner)",
            rp2040js.display()
        ));
    }
    if crate::emulator::defmt_print().is_none() {
        return Some(
            "defmt-print is not installed (scripts/setup.d/30-hil.sh: `cargo install defmt-print --locked`)"
                .into(),
        );
    }
    None
}

impl RealBoard {
    fn start(port: PathBuf) -> Result<Self> {
        let logs = Arc::new(Mutex::new(Vec::new()));
        let mut probe = None;
        if std::env::var_os("DBOT_HIL_FLASH").is_none_or(|v| v != "0") {
            let elf = crate::paths::firmware_elf();
            let mut child = Command::new("probe-rs")
                .args(["run", "--chip", "RP2040"])
                .arg(&elf)
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .spawn()
                .context(
                    "cannot run `probe-rs run` to flash the board (set DBOT_HIL_FLASH=0 to skip)",
                )?;
            for pipe in [
                child
                    .stdout
                    .take()
                    .map(|p| Box::new(p) as Box<dyn std::io::Read + Send>),
                child
                    .stderr
                    .take()
                    .map(|p| Box::new(p) as Box<dyn std::io::Read + Send>),
            ]
            .into_iter()
            .flatten()
            {
                let logs = logs.clone();
                std::thread::spawn(move || {
                    for line in BufReader::new(pipe).lines().map_while(Result::ok) {
                        println!("[board] {line}");
                        logs.lock().unwrap().push(line);
                    }
                });
            }
            probe = Some(child);
        }
        // Flashing and USB enumeration take a few seconds; wait for the port to (re)appear.
        let started = Instant::now();
        std::thread::sleep(Duration::from_secs(1));
        while !port.exists() {
            if started.elapsed() > Duration::from_secs(30) {
                bail!("{} did not appear within 30 s of flashing", port.display());
            }
            std::thread::sleep(Duration::from_millis(200));
        }
        Ok(Self { port, probe, logs })
    }

    fn wait_for_log(&self, needle: &str, timeout: Duration) -> Result<String> {
        if self.probe.is_none() {
            bail!("no log stream: the board was not started through probe-rs (DBOT_HIL_FLASH=0)");
        }
        let started = Instant::now();
        loop {
            if let Some(l) = self
                .logs
                .lock()
                .unwrap()
                .iter()
                .find(|l| l.contains(needle))
            {
                return Ok(l.clone());
            }
            if started.elapsed() > timeout {
                bail!("no log line containing {needle:?} within {timeout:?}");
            }
            std::thread::sleep(Duration::from_millis(50));
        }
    }
}

impl Drop for RealBoard {
    fn drop(&mut self) {
        if let Some(mut c) = self.probe.take() {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

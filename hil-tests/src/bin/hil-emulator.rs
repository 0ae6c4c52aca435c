//! `hil-emulator`: the emulated Drosophibot II board as a program of its own, for clients that are
//! not Rust tests (the Python package's pytest fixture, a researcher trying a controller without a
//! robot). It starts the release firmware image in the RP2040 emulator (hil-tests/runner) with the
//! `hil-bus` virtual servo chain on its bus, prints `PORT /dev/pts/N` on stdout once the board's
//! USB is up, and runs until stdin closes or it gets SIGTERM/SIGINT; then it stops the runner,
//! which ends the servo chain and defmt-print (no orphan processes).
//!
//! Exit status: 0 after a clean stop, 3 when a prerequisite is missing (the message names the
//! setup command), 2 for bad options, 1 on any other error.

use anyhow::{Context, Result, bail};
use clap::Parser;
use hil_tests::{Echo, Emulator, Options};
use nix::sys::signal::{SigSet, Signal};
use std::io::{Read, Write};
use std::path::PathBuf;
use std::sync::mpsc;
use std::time::Duration;

/// Runs the release firmware image on an emulated RP2040 with virtual servos on its bus and
/// serves its USB port as a pty. Stops when stdin closes or on SIGTERM/SIGINT.
#[derive(Debug, Parser)]
#[command(name = "hil-emulator")]
struct Args {
    /// Virtual servos on the bus (IDs 1..=N; MX-64 on the CTr joints as on the robot).
    #[arg(long, default_value_t = 22)]
    servos: u8,
    /// Baud rate of the virtual servos, bit/s. The firmware boots at 1 Mbit/s; a board set to
    /// another rate (SetBus) reaches servos only at the rate given here.
    #[arg(long, default_value_t = 1_000_000)]
    baud: u32,
    /// Flash persistence file (2 MB, created on first write): keeps the gait store across runs.
    /// Default: a fresh erased flash every run.
    #[arg(long)]
    flash: Option<PathBuf>,
    /// The firmware ELF. Default: DBOT_HIL_ELF, else target/thumbv6m-none-eabi/release/firmware.
    #[arg(long)]
    elf: Option<PathBuf>,
    /// Forward the firmware's decoded defmt log (with simulated time, s) and the runner's notices
    /// to stderr.
    #[arg(long)]
    log: bool,
    /// Keep simulated time at most this multiple of wall time (default: as fast as it runs).
    #[arg(long)]
    realtime: Option<f64>,
    /// Process ID of the host (e.g. the pytest process): simulated time passes only while every
    /// thread of it (and of this program, which carries its bytes through the pty) is blocked,
    /// as on the in-process virtual robot, so a host slowed by a loaded machine never falls
    /// behind the board's clock (runner/src/pace.js). Default: simulated time runs freely.
    #[arg(long, value_name = "PID")]
    paced_by: Option<u32>,
}

/// Exit status for a missing prerequisite, so a caller can tell "not installed" from a failure.
const MISSING: i32 = 3;
/// Simulated time the firmware gets to boot and see the host (it boots in a few ms).
const BOOT: Duration = Duration::from_secs(5);

fn main() {
    let args = Args::parse();
    // Before any thread exists, so every thread inherits the mask and only `sigwait` sees them.
    // Children get a clean mask: std's Command resets it in the child before exec.
    let mut signals = SigSet::empty();
    signals.add(Signal::SIGTERM);
    signals.add(Signal::SIGINT);
    if let Err(e) = signals.thread_block() {
        eprintln!("hil-emulator: cannot block SIGTERM/SIGINT: {e}");
        std::process::exit(1);
    }
    let opts = match options(&args) {
        Ok(o) => o,
        Err(why) => {
            eprintln!("hil-emulator: cannot start the emulated board: {why:#}");
            std::process::exit(MISSING);
        }
    };
    if let Err(e) = run(opts, signals) {
        eprintln!("hil-emulator: {e:#}");
        std::process::exit(1);
    }
}

/// The emulator options, or why a prerequisite is missing.
fn options(args: &Args) -> Result<Options> {
    let exe = std::env::current_exe().context("cannot find this program's path")?;
    let hil_bus = exe.with_file_name("hil-bus");
    if !hil_bus.is_file() {
        bail!(
            "no servo chain program at {} (build it with `cargo build -p hil-tests --bins`)",
            hil_bus.display()
        );
    }
    let opts = Options {
        elf: args.elf.clone(),
        flash_file: args.flash.clone(),
        bus: Some(hil_tests::drive::servo_bus(
            &hil_bus.to_string_lossy(),
            usize::from(args.servos),
            args.baud,
        )),
        realtime: args.realtime,
        paced_by: args
            .paced_by
            .map(|host| vec![host, std::process::id()])
            .unwrap_or_default(),
        echo: if args.log { Echo::Stderr } else { Echo::Off },
    };
    if let Some(why) = hil_tests::target::emulator_missing(&opts) {
        bail!("{why}");
    }
    Ok(opts)
}

/// Why the program stops.
#[derive(Debug)]
enum Stop {
    StdinClosed,
    Signal(Signal),
}

fn run(opts: Options, signals: SigSet) -> Result<()> {
    let emu = Emulator::start(opts)?;
    emu.wait_for_log("host connected", BOOT)
        .context("the firmware did not bring up its USB port")?;
    {
        let mut out = std::io::stdout().lock();
        writeln!(out, "PORT {}", emu.port().display())?;
        out.flush()?;
    }
    let (tx, rx) = mpsc::channel();
    let on_stdin = tx.clone();
    std::thread::spawn(move || {
        let mut buf = [0u8; 256];
        let mut stdin = std::io::stdin().lock();
        while matches!(stdin.read(&mut buf), Ok(n) if n > 0) {}
        let _ = on_stdin.send(Stop::StdinClosed);
    });
    std::thread::spawn(move || {
        if let Ok(sig) = signals.wait() {
            let _ = tx.send(Stop::Signal(sig));
        }
    });
    loop {
        match rx.recv_timeout(Duration::from_millis(500)) {
            Ok(stop) => {
                let why = match stop {
                    Stop::StdinClosed => "stdin closed".to_string(),
                    Stop::Signal(sig) => sig.to_string(),
                };
                eprintln!("hil-emulator: stopping ({why})");
                // Dropping the emulator quits the runner, which ends the servo chain and
                // defmt-print; a runner that does not quit within 2 s is killed.
                drop(emu);
                return Ok(());
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {
                // A runner that died (firmware halted the core, servo chain crashed) must not
                // leave a port that silently stopped answering.
                emu.sim_time().context("the emulator runner stopped")?;
            }
            Err(mpsc::RecvTimeoutError::Disconnected) => bail!("lost the stop watchers"),
        }
    }
}

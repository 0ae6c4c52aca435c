//! `dbot sim-strain`: serves a virtual strain board on a pseudo-terminal until interrupted,
//! speaking the lab's board's protocol, with faults on demand.

use anyhow::Context as _;
use board::strain::pty::StrainPtyServer;
use board::strain::source::{Constant, Recording, StrainSource, Synthetic};
use board::strain::virtual_board::{DEFAULT_GAIN, Ended, Fault, VirtualStrainBoard};
use std::io::Write as _;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use crate::common::interrupt;

/// Serve a virtual strain board (the lab's 36-gauge board) on a pseudo-terminal.
///
/// Like the real board it resets when a client opens the port: it prints `Waiting on MATLAB...`,
/// calibrates on a non-zero byte, then streams 36 counts per line (baseline 300 + gain x strain,
/// saturating at 0 and 1023) at the pace of its 115200 bit/s line, while the last byte was non-zero.
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot sim-strain --link /tmp/strain                                   # every gauge at its baseline
  dbot sim-strain --link /tmp/strain --fault no-calibrate:RM_femur_axial --fault noise:3
  dbot sim-strain --link /tmp/strain --from-csv rec/strain.csv         # replay a recording
  dbot strain --port /tmp/strain                                       # (in another shell)")]
pub struct Args {
    /// Path of the symlink to the pseudo-terminal: what clients open as their serial port
    #[arg(long)]
    link: PathBuf,
    /// A fault (repeatable): unplugged:GAUGE, no-calibrate:GAUGE, noise:COUNTS,
    /// reset-at:SAMPLES, hangup-at:SAMPLES (the board goes away), garbage-at:SAMPLES (that sample
    /// garbled), no-done
    #[arg(long = "fault", value_parser = Fault::parse)]
    faults: Vec<Fault>,
    /// Replay a strain recording (strain.csv: a column of raw counts per gauge) instead of strain
    #[arg(long, conflicts_with_all = ["strain", "sine_hz"])]
    from_csv: Option<PathBuf>,
    /// Strain at every gauge, microstrain (the amplitude with --sine-hz)
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    strain: f64,
    /// Make the strain a sine of this frequency, Hz (each leg half a cycle after the one before)
    #[arg(long)]
    sine_hz: Option<f64>,
    /// Counts per microstrain (an invented default: the lab's gain is not published)
    #[arg(long, default_value_t = DEFAULT_GAIN)]
    gain: f64,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        let source: Box<dyn StrainSource> = match (&self.from_csv, self.sine_hz) {
            (Some(p), _) => Box::new(Recording::load(p)?),
            (None, Some(hz)) => Box::new(Synthetic {
                amplitude: self.strain,
                hz,
            }),
            (None, None) => Box::new(Constant(self.strain)),
        };
        let board = VirtualStrainBoard::new(source, self.faults.clone(), true).with_gain(self.gain);
        let mut server = StrainPtyServer::open(board, &self.link).with_context(|| {
            format!(
                "cannot serve the virtual strain board at {}",
                self.link.display()
            )
        })?;
        interrupt::catch()?;
        println!(
            "serving a virtual strain board on {} linked at {}{}; Ctrl-C stops",
            server.slave_path(),
            self.link.display(),
            if self.faults.is_empty() {
                String::new()
            } else {
                format!(", {} faults", self.faults.len())
            }
        );
        std::io::stdout().flush().ok();
        let stop = Arc::new(AtomicBool::new(false));
        let s = stop.clone();
        std::thread::spawn(move || {
            while !interrupt::requested() {
                std::thread::sleep(Duration::from_millis(50));
            }
            s.store(true, Ordering::Relaxed);
        });
        let ended = server
            .serve(&stop, |e| println!("{}", describe(e)))
            .context("serving the virtual strain board failed")?;
        match ended {
            Ended::HungUp(n) => println!("gone after {n} samples (hangup-at fault)"),
            Ended::Stopped | Ended::HostGone => println!("stopped"),
        }
        Ok(())
    }
}

fn describe(e: &Ended) -> &'static str {
    match e {
        Ended::Stopped => "session stopped",
        Ended::HostGone => "client closed the port; the board resets for the next one",
        Ended::HungUp(_) => "hung up (the hangup-at fault)",
    }
}

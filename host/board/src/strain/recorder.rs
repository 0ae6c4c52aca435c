//! [`StrainRecorder`]: records the strain board on a thread of its own beside any other
//! recording, into `strain.csv` (tidy: `time_s` then one column of raw counts per gauge, named
//! `LF_troch_axial`...; a row per sample, flushed as it is written) and `strain_baseline.csv`
//! (the method and the zero-strain counts per gauge: the first sample of the trial). No gain is
//! known by default, so no microstrain columns are written.
//!
//! Time base: `time_s` is host time since the `epoch` the caller gives: pass the instant the
//! other recording calls its time zero, and both files share one clock. A row's time is the
//! instant its line ended (see the driver: the readings lie 0 to about 24 ms before it, estimate).
//!
//! Failure of the strain board never reaches the caller's recording: the thread ends, the file
//! keeps every row it had, and [`StrainRecorder::finish`] returns the error naming the port.
//!
//! While it runs, [`StrainRecorder::latest`] gives the latest sample with its host instant and
//! the baseline (a closed loop reads it: strain beside each proprioception record).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::Instant;

use super::baseline::Baseline;
use super::calibration::CalibrationReport;
use super::channels;
use super::driver::{StrainBoard, Timeouts};
use super::error::StrainError;
use super::port::{self, StrainIo};
use super::stats::{GaugeStats, Stuck};

/// The strain file's name in a recording folder.
pub const STRAIN_CSV: &str = "strain.csv";
/// The baseline file's name.
pub const BASELINE_CSV: &str = "strain_baseline.csv";

/// What a finished strain recording holds.
#[derive(Debug, Clone, PartialEq)]
pub struct StrainRecording {
    pub port: String,
    pub csv: PathBuf,
    pub samples: u64,
    pub calibration: CalibrationReport,
    pub stuck: Vec<Stuck>,
}

impl std::fmt::Display for StrainRecording {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "strain: {} samples of 36 gauges from {} in {}",
            self.samples,
            self.port,
            self.csv.display()
        )?;
        for n in &self.calibration.not_calibrated {
            write!(f, "; {} would not calibrate", n.channel.name())?;
        }
        for s in &self.stuck {
            write!(f, "; {s}")?;
        }
        Ok(())
    }
}

/// A strain recording that stopped early; the file keeps what was read.
#[derive(Debug, thiserror::Error)]
#[error("strain recording stopped: {source}; {samples} samples kept in {}", csv.display())]
pub struct StrainRecordError {
    pub samples: u64,
    pub csv: PathBuf,
    pub source: StrainError,
}

/// The latest sample of a running strain recording.
#[derive(Debug, Clone, PartialEq)]
pub struct LatestSample {
    /// The host instant its line ended (the readings lie 0 to about 24 ms before it, ESTIMATE).
    pub host: Instant,
    pub counts: super::line::Counts,
    /// The recording's zero-strain baseline (its first sample, as the lab takes it).
    pub baseline: super::line::Counts,
}

/// Where the recorder's thread leaves its latest sample.
type Latest = Arc<Mutex<Option<LatestSample>>>;

/// A strain board recorded on its own thread.
#[derive(Debug)]
pub struct StrainRecorder {
    stop: Arc<AtomicBool>,
    samples: Arc<AtomicU64>,
    latest: Latest,
    thread: Option<JoinHandle<Result<StrainRecording, StrainRecordError>>>,
}

impl StrainRecorder {
    /// Starts recording the strain board on `port` (a serial path or `virtual`) into `dir`,
    /// with `time_s` measured from `epoch`. Refuses at once a port that is the servo board's
    /// `servo_port`; every other failure comes from [`StrainRecorder::finish`].
    pub fn start(
        port: &str,
        servo_port: &str,
        dir: &Path,
        epoch: Instant,
    ) -> Result<Self, StrainError> {
        Self::start_fed(port, servo_port, dir, epoch, None)
    }

    /// [`Self::start`], the `virtual` board's gauges reading `feed` (the physics robot's
    /// simulated gauges) when given.
    pub fn start_fed(
        port: &str,
        servo_port: &str,
        dir: &Path,
        epoch: Instant,
        feed: Option<super::source::Shared>,
    ) -> Result<Self, StrainError> {
        port::check_not_servo_port(port, servo_port)?;
        let name = port.to_owned();
        let dir = dir.to_path_buf();
        Ok(Self::spawn(move |stop, n, latest| {
            let io = port::open_fed(&name, feed).map_err(|source| StrainRecordError {
                samples: 0,
                csv: dir.join(STRAIN_CSV),
                source,
            })?;
            record(
                io,
                &name,
                &dir,
                epoch,
                Timeouts::default(),
                &stop,
                &n,
                &latest,
            )
        }))
    }

    /// The same on an already open byte stream named `port` (tests, other transports).
    pub fn start_on(
        io: Box<dyn StrainIo>,
        port: &str,
        dir: &Path,
        epoch: Instant,
        timeouts: Timeouts,
    ) -> Self {
        let name = port.to_owned();
        let dir = dir.to_path_buf();
        Self::spawn(move |stop, n, latest| {
            record(io, &name, &dir, epoch, timeouts, &stop, &n, &latest)
        })
    }

    fn spawn(
        body: impl FnOnce(
            Arc<AtomicBool>,
            Arc<AtomicU64>,
            Latest,
        ) -> Result<StrainRecording, StrainRecordError>
        + Send
        + 'static,
    ) -> Self {
        let stop = Arc::new(AtomicBool::new(false));
        let samples = Arc::new(AtomicU64::new(0));
        let latest = Latest::default();
        let (s, n, l) = (stop.clone(), samples.clone(), latest.clone());
        Self {
            stop,
            samples,
            latest,
            thread: Some(std::thread::spawn(move || body(s, n, l))),
        }
    }

    /// The latest sample and the baseline (None before the first sample). After the board
    /// failed it stays the last one read.
    pub fn latest(&self) -> Option<LatestSample> {
        self.latest
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
    }

    /// Samples written so far.
    pub fn samples(&self) -> u64 {
        self.samples.load(Ordering::Relaxed)
    }

    /// Whether the recording has ended by itself (the board failed or went away).
    pub fn ended(&self) -> bool {
        self.thread.as_ref().is_none_or(JoinHandle::is_finished)
    }

    /// Stops the board's stream and returns what was recorded, or why it stopped early.
    pub fn finish(mut self) -> Result<StrainRecording, StrainRecordError> {
        self.stop.store(true, Ordering::Relaxed);
        let thread = self.thread.take().expect("joined only here or in drop");
        thread.join().unwrap_or_else(|_| {
            panic!("the strain recorder's thread panicked");
        })
    }
}

impl Drop for StrainRecorder {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// The recorder's thread: calibrate, then a row per sample until `stop`.
#[allow(clippy::too_many_arguments)]
fn record(
    io: Box<dyn StrainIo>,
    port: &str,
    dir: &Path,
    epoch: Instant,
    timeouts: Timeouts,
    stop: &AtomicBool,
    written: &AtomicU64,
    latest: &Latest,
) -> Result<StrainRecording, StrainRecordError> {
    let csv = dir.join(STRAIN_CSV);
    let fail = |samples, source| StrainRecordError {
        samples,
        csv: csv.clone(),
        source,
    };
    let file_err = |path: &Path, source| StrainError::File {
        path: path.display().to_string(),
        source,
    };
    let mut out = File::create(&csv)
        .map(BufWriter::new)
        .map_err(|e| fail(0, file_err(&csv, e)))?;
    writeln!(out, "time_s,{}", channels::names().join(","))
        .and_then(|()| out.flush())
        .map_err(|e| fail(0, file_err(&csv, e)))?;
    let mut board = StrainBoard::new(io, port, timeouts);
    let calibration = board.calibrate().map_err(|e| fail(0, e))?;
    let mut stats = GaugeStats::default();
    let mut baseline = None;
    while !stop.load(Ordering::Relaxed) {
        let sample = board.next_sample().map_err(|e| fail(stats.samples(), e))?;
        let base = *baseline.get_or_insert(sample.counts);
        *latest.lock().unwrap_or_else(|e| e.into_inner()) = Some(LatestSample {
            host: sample.host,
            counts: sample.counts,
            baseline: base,
        });
        if stats.samples() == 0 {
            let b = dir.join(BASELINE_CSV);
            write_baseline(&b, &Baseline::first_sample(&sample.counts))
                .map_err(|e| fail(0, file_err(&b, e)))?;
        }
        let t = match sample.host.checked_duration_since(epoch) {
            Some(d) => d.as_secs_f64(),
            None => -(epoch - sample.host).as_secs_f64(),
        };
        let row: Vec<String> = sample.counts.iter().map(f64::to_string).collect();
        writeln!(out, "{t:.6},{}", row.join(","))
            .and_then(|()| out.flush())
            .map_err(|e| fail(stats.samples(), file_err(&csv, e)))?;
        stats.add(&sample.counts);
        written.store(stats.samples(), Ordering::Relaxed);
    }
    // The stream is stopped for the next user; a board gone by now loses nothing recorded.
    let _ = board.stop();
    Ok(StrainRecording {
        port: port.to_owned(),
        csv,
        samples: stats.samples(),
        calibration,
        stuck: stats.stuck(),
    })
}

/// `method,<gauge names>` and one row.
pub fn write_baseline(path: &Path, b: &Baseline) -> std::io::Result<()> {
    let row: Vec<String> = b.counts.iter().map(f64::to_string).collect();
    std::fs::write(
        path,
        format!(
            "method,{}\n{},{}\n",
            channels::names().join(","),
            b.method.name(),
            row.join(",")
        ),
    )
}

//! The strain board recorded beside a servo recording, on the servo board's clock: the one way
//! `dbot record --strain` and Python's `Board.record(..., strain=)` wire a [`StrainRecorder`]
//! into a recording, so both refuse and align alike.
//!
//! [`StrainBeside::start`] refuses the servo board's port, starts the recorder (host clock from
//! the instant of the start), and returns once the board is calibrated and its first sample (the
//! trial's zero-strain baseline) is in, so the robot moves only after that. The caller notes each
//! telemetry record as it arrives ([`StrainBeside::note`]); [`StrainBeside::finish`] fits the
//! host-to-board clock map ([`super::clock`]) and rewrites `strain.csv` with `time_s` on the
//! telemetry's time base (board seconds since the first telemetry record) beside the host's
//! `host_s`, and writes the fit to `strain_clock.csv`.
//!
//! A strain board that fails mid-recording only ends the strain thread: the servo recording goes
//! on, the strain rows so far are aligned and kept, and the end says why it stopped.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use super::channels::{self, CHANNELS};
use super::clock::{ClockFit, ClockMap};
use super::driver::Timeouts;
use super::error::StrainError;
use super::line::Counts;
use super::port::StrainIo;
use super::recorder::{STRAIN_CSV, StrainRecordError, StrainRecorder, StrainRecording};

/// The clock fit's file in a recording folder.
pub const CLOCK_CSV: &str = "strain_clock.csv";

/// A strain board recording beside a servo recording.
#[derive(Debug)]
pub struct StrainBeside {
    recorder: StrainRecorder,
    epoch: Instant,
    clock: ClockMap,
    dir: PathBuf,
}

/// How a strain recording beside a servo recording ended.
#[derive(Debug)]
pub struct StrainEnd {
    /// What was recorded, or why the strain stream stopped early (its rows are kept).
    pub recording: Result<StrainRecording, StrainRecordError>,
    /// The clock map the rows were aligned with (None: no telemetry record arrived, `time_s` is
    /// empty), or why `strain.csv` could not be rewritten (it then keeps host time).
    pub clock: Result<Option<ClockFit>, StrainError>,
}

impl StrainBeside {
    /// Starts the strain board on `port` (a serial path or `virtual`) recording into `dir`
    /// beside the servo board on `servo_port` (refused as the strain port, by name), and waits
    /// until it has calibrated and sent its first sample. Its failure to get there is the error.
    pub fn start(port: &str, servo_port: &str, dir: &Path) -> Result<Self, StrainError> {
        Self::start_fed(port, servo_port, dir, None)
    }

    /// [`Self::start`], a `virtual` strain board's gauges reading `feed` when given: the physics
    /// robot's simulated gauges (`physics::PhysicsRobot::feed_strain`).
    pub fn start_fed(
        port: &str,
        servo_port: &str,
        dir: &Path,
        feed: Option<super::source::Shared>,
    ) -> Result<Self, StrainError> {
        let epoch = Instant::now();
        let recorder = StrainRecorder::start_fed(port, servo_port, dir, epoch, feed)?;
        Self::ready(recorder, epoch, dir)
    }

    /// The same on an open byte stream named `port` (tests, other transports).
    pub fn start_on(
        io: Box<dyn StrainIo>,
        port: &str,
        dir: &Path,
        timeouts: Timeouts,
    ) -> Result<Self, StrainError> {
        let epoch = Instant::now();
        Self::ready(
            StrainRecorder::start_on(io, port, dir, epoch, timeouts),
            epoch,
            dir,
        )
    }

    fn ready(recorder: StrainRecorder, epoch: Instant, dir: &Path) -> Result<Self, StrainError> {
        // The recorder's own deadlines (banner, calibration, sample) bound this wait.
        while recorder.samples() == 0 {
            if recorder.ended() {
                return match recorder.finish() {
                    Err(e) => Err(e.source),
                    Ok(r) => Err(StrainError::NoSample {
                        port: r.port,
                        waited_s: 0.0,
                    }),
                };
            }
            std::thread::sleep(Duration::from_millis(2));
        }
        Ok(Self {
            recorder,
            epoch,
            clock: ClockMap::default(),
            dir: dir.to_path_buf(),
        })
    }

    /// A telemetry record of board time `board_s` (the servo CSV's `time_s`) arrived just now.
    pub fn note(&mut self, board_s: f64) {
        self.clock.note(self.epoch.elapsed().as_secs_f64(), board_s);
    }

    /// Strain samples written so far.
    pub fn samples(&self) -> u64 {
        self.recorder.samples()
    }

    /// The latest strain sample and the baseline ([`super::recorder::StrainRecorder::latest`]).
    pub fn latest(&self) -> Option<super::recorder::LatestSample> {
        self.recorder.latest()
    }

    /// Whether the strain stream has stopped by itself (the board failed or went away).
    pub fn failed(&self) -> bool {
        self.recorder.ended()
    }

    /// Stops the strain board, then aligns the rows it kept with the servo board's clock.
    pub fn finish(self) -> StrainEnd {
        let recording = self.recorder.finish();
        let fit = self.clock.fit();
        let clock = align(&self.dir, fit).map(|()| fit);
        StrainEnd { recording, clock }
    }
}

/// Rewrites `dir/strain.csv` (`time_s` host seconds, then the gauges) as `time_s` on the board's
/// clock (empty without a fit), `host_s`, then the gauges; writes `strain_clock.csv`.
fn align(dir: &Path, fit: Option<ClockFit>) -> Result<(), StrainError> {
    let csv = dir.join(STRAIN_CSV);
    let file_err = |path: &Path, source| StrainError::File {
        path: path.display().to_string(),
        source,
    };
    let text = std::fs::read_to_string(&csv).map_err(|e| file_err(&csv, e))?;
    let mut out = format!("time_s,host_s,{}\n", channels::names().join(","));
    for line in text.lines().skip(1).filter(|l| !l.trim().is_empty()) {
        let (host, gauges) = line.split_once(',').unwrap_or((line, ""));
        let board = match (fit, host.trim().parse::<f64>()) {
            (Some(f), Ok(h)) => format!("{:.6}", f.board_s(h)),
            _ => String::new(),
        };
        out.push_str(&format!("{board},{host},{gauges}\n"));
    }
    let tmp = dir.join(".strain.csv.aligning");
    std::fs::write(&tmp, out).map_err(|e| file_err(&tmp, e))?;
    std::fs::rename(&tmp, &csv).map_err(|e| file_err(&csv, e))?;
    let clock = dir.join(CLOCK_CSV);
    let row = fit.map_or_else(
        || ",,0,".to_owned(),
        |f| {
            format!(
                "{:.9},{:.6},{},{:.6}",
                f.rate, f.offset_s, f.records, f.jitter_p95_s
            )
        },
    );
    std::fs::write(
        &clock,
        format!("host_s_per_board_s,host_s_at_board_0,records,jitter_p95_s\n{row}\n"),
    )
    .map_err(|e| file_err(&clock, e))
}

/// An aligned strain file read back: board time (None where no clock map was known) and counts.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AlignedStrain {
    pub time_s: Vec<Option<f64>>,
    pub counts: Vec<Counts>,
}

/// Reads a `strain.csv` that [`StrainBeside::finish`] aligned (columns found by name).
pub fn read_aligned(path: &Path) -> Result<AlignedStrain, StrainError> {
    let p = path.display().to_string();
    let bad = |what: String| StrainError::File {
        path: p.clone(),
        source: std::io::Error::new(std::io::ErrorKind::InvalidData, what),
    };
    let text = std::fs::read_to_string(path).map_err(|source| StrainError::File {
        path: p.clone(),
        source,
    })?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| h.trim() == name)
            .ok_or_else(|| bad(format!("no column `{name}`")))
    };
    let t = col("time_s")?;
    let names = channels::names();
    let index: Vec<usize> = names.iter().map(|n| col(n)).collect::<Result<_, _>>()?;
    let mut out = AlignedStrain::default();
    for (i, l) in lines.enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let cells: Vec<&str> = l.split(',').collect();
        let cell = |c: usize| cells.get(c).map_or("", |s| s.trim());
        out.time_s.push(cell(t).parse::<f64>().ok());
        let mut row = [0.0; CHANNELS];
        for (c, &k) in index.iter().enumerate() {
            row[c] = cell(k).parse::<f64>().map_err(|_| {
                bad(format!(
                    "line {}, column `{}`: `{}` is not a count",
                    i + 2,
                    names[c],
                    cell(k)
                ))
            })?;
        }
        out.counts.push(row);
    }
    Ok(out)
}

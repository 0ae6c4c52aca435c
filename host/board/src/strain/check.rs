//! The board check behind `dbot strain`: calibrate, read the stream for a while, stop it, and
//! say what was found (gauges that would not calibrate and their values, channels stuck at a rail,
//! per-gauge means). A broken gauge is the calibration's error ([`StrainError::Broken`]).

use std::io::{Read, Write};
use std::time::{Duration, Instant};

use super::calibration::CalibrationReport;
use super::driver::StrainBoard;
use super::error::StrainError;
use super::line::Counts;
use super::stats::{GaugeStats, Stuck};

/// What a check found.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckReport {
    pub calibration: CalibrationReport,
    pub samples: u64,
    /// Mean counts per channel over the samples, in column order.
    pub means: Counts,
    pub stuck: Vec<Stuck>,
}

impl CheckReport {
    /// Whether every gauge calibrated and none is stuck.
    pub fn all_good(&self) -> bool {
        self.calibration.not_calibrated.is_empty() && self.stuck.is_empty()
    }
}

/// Calibrates `board`, reads it for `read_for` (at least one sample), and stops its stream.
pub fn check<T: Read + Write>(
    board: &mut StrainBoard<T>,
    read_for: Duration,
) -> Result<CheckReport, StrainError> {
    let calibration = board.calibrate()?;
    let mut stats = GaugeStats::default();
    let start = Instant::now();
    while stats.samples() == 0 || start.elapsed() < read_for {
        stats.add(&board.next_sample()?.counts);
    }
    board.stop()?;
    Ok(CheckReport {
        calibration,
        samples: stats.samples(),
        means: stats.means().expect("at least one sample"),
        stuck: stats.stuck(),
    })
}

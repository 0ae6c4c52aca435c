//! What a virtual strain board reads on its gauges: a [`StrainSource`] gives each sample either
//! strain (microstrain, turned into counts by the board as baseline + gain x strain) or raw counts
//! (a recording replayed). The physics robot's simulated gauges can feed a board through it.

use std::path::Path;
use std::sync::{Arc, Mutex};

use super::channels::{self, CHANNELS};
use super::line::Counts;

/// One sample of a source.
#[derive(Debug, Clone, PartialEq)]
pub enum Reading {
    /// Strain at each gauge, microstrain, in column order.
    Microstrain([f64; CHANNELS]),
    /// Raw counts, in column order (a recording).
    Counts(Counts),
}

/// Feeds a virtual strain board, one reading per sample line.
pub trait StrainSource: Send {
    /// Reading for sample `k` (0-based) taken at `t_s` seconds of streaming.
    fn reading(&mut self, k: u64, t_s: f64) -> Reading;
}

/// The same strain on every gauge at every sample (zero: the board streams its baseline).
#[derive(Debug, Clone, PartialEq)]
pub struct Constant(pub f64);

impl StrainSource for Constant {
    fn reading(&mut self, _k: u64, _t_s: f64) -> Reading {
        Reading::Microstrain([self.0; CHANNELS])
    }
}

/// A sine per gauge: `amplitude` microstrain at `hz`, each leg half a cycle after the one before
/// (a stand-in for stepping; not a model of any gait).
#[derive(Debug, Clone, PartialEq)]
pub struct Synthetic {
    pub amplitude: f64,
    pub hz: f64,
}

impl StrainSource for Synthetic {
    fn reading(&mut self, _k: u64, t_s: f64) -> Reading {
        let mut out = [0.0; CHANNELS];
        for (i, v) in out.iter_mut().enumerate() {
            let leg = (i / channels::GAUGES_PER_LEG) as f64;
            *v = self.amplitude
                * (std::f64::consts::TAU * self.hz * t_s + leg * std::f64::consts::PI).sin();
        }
        Reading::Microstrain(out)
    }
}

/// Strain set from outside the board's thread (the physics robot's simulated gauges, sampled as
/// it walks): every sample line reads the latest value set, microstrain, in column order.
#[derive(Debug, Clone)]
pub struct Shared(Arc<Mutex<[f64; CHANNELS]>>);

impl Default for Shared {
    /// Zero strain until set.
    fn default() -> Self {
        Self(Arc::new(Mutex::new([0.0; CHANNELS])))
    }
}

impl Shared {
    /// Sets the strain the next sample lines read.
    pub fn set(&self, microstrain: [f64; CHANNELS]) {
        *self.0.lock().unwrap_or_else(|e| e.into_inner()) = microstrain;
    }
}

impl StrainSource for Shared {
    fn reading(&mut self, _k: u64, _t_s: f64) -> Reading {
        Reading::Microstrain(*self.0.lock().unwrap_or_else(|e| e.into_inner()))
    }
}

/// Errors reading a recording to replay.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SourceError {
    #[error("cannot read {path}: {source}")]
    Read {
        path: String,
        source: std::io::Error,
    },
    #[error("{path}: no column `{column}` (a strain recording has one per gauge)")]
    MissingColumn { path: String, column: String },
    #[error("{path} line {line}, column `{column}`: `{text}` is not a count 0..1023")]
    BadValue {
        path: String,
        line: usize,
        column: String,
        text: String,
    },
    #[error("{path}: no samples")]
    Empty { path: String },
}

/// A strain recording (`strain.csv`: a header with a column per gauge name, raw counts) replayed
/// row by row, from the start again at its end.
#[derive(Debug, Clone, PartialEq)]
pub struct Recording {
    rows: Vec<Counts>,
}

impl Recording {
    pub fn load(path: &Path) -> Result<Self, SourceError> {
        let p = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| SourceError::Read {
            path: p.clone(),
            source,
        })?;
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
        let mut index = [0usize; CHANNELS];
        for (c, name) in channels::names().iter().enumerate() {
            index[c] = header
                .iter()
                .position(|h| h.trim() == name)
                .ok_or_else(|| SourceError::MissingColumn {
                    path: p.clone(),
                    column: name.clone(),
                })?;
        }
        let names = channels::names();
        let mut rows = Vec::new();
        for (i, l) in lines.enumerate() {
            if l.trim().is_empty() {
                continue;
            }
            let cells: Vec<&str> = l.split(',').collect();
            let mut row = [0.0; CHANNELS];
            for c in 0..CHANNELS {
                let text = cells.get(index[c]).copied().unwrap_or("").trim();
                row[c] = text
                    .parse::<f64>()
                    .ok()
                    .filter(|v| (0.0..=super::line::MAX_COUNT).contains(v))
                    .ok_or_else(|| SourceError::BadValue {
                        path: p.clone(),
                        line: i + 2,
                        column: names[c].clone(),
                        text: text.to_owned(),
                    })?;
            }
            rows.push(row);
        }
        if rows.is_empty() {
            return Err(SourceError::Empty { path: p });
        }
        Ok(Self { rows })
    }
}

impl StrainSource for Recording {
    fn reading(&mut self, k: u64, _t_s: f64) -> Reading {
        Reading::Counts(self.rows[(k % self.rows.len() as u64) as usize])
    }
}

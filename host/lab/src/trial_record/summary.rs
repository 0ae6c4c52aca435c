//! What a recorded trial holds, in the one line `dbot record` prints (and Python shows).

use std::fmt;
use std::path::{Path, PathBuf};

use board::strain::StrainEnd;

use crate::error::Result;

/// A trial recorded and published by [`super::record_trial`].
#[derive(Debug, Clone, PartialEq)]
pub struct TrialSummary {
    /// The published trial folder.
    pub path: PathBuf,
    /// Bus cycles recorded.
    pub cycles: usize,
    /// Board time recorded, s.
    pub duration_s: f64,
    /// Joints recorded.
    pub joints: usize,
    /// Telemetry records missing (skipped cycle numbers).
    pub missing_records: u64,
    /// Of those, records dropped on the board or the host (`None`: not known).
    pub lost_records: Option<u64>,
    /// The strain board's recording and its clock, when one recorded beside the servos.
    pub strain: Option<String>,
}

impl fmt::Display for TrialSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "recorded {} bus cycles ({:.2} s of board time) x {} joints: trial {}; ",
            self.cycles,
            self.duration_s,
            self.joints,
            self.path.display()
        )?;
        f.write_str(&board::record::missing_words(
            self.missing_records,
            self.lost_records,
        ))?;
        match &self.strain {
            Some(line) => write!(f, "\n{line}"),
            None => Ok(()),
        }
    }
}

/// The strain line of the summary, or the error of a strain stream that stopped early (the
/// servo recording is whole in `trial` by then).
pub(super) fn strain_summary(end: StrainEnd, trial: &str) -> Result<String> {
    let clock = match end.clock {
        Ok(Some(f)) => format!(
            "; strain on the board's clock (host {:.6} s per board s, telemetry jitter {:.1} ms \
             at the 95th percentile)",
            f.rate,
            f.jitter_p95_s * 1e3
        ),
        Ok(None) => "; strain not aligned: no telemetry arrived".to_owned(),
        Err(e) => format!("; strain kept on host time: {e}"),
    };
    // The recorder wrote into the unpublished folder: name the file where it is now.
    let csv = Path::new(trial).join(board::strain::recorder::STRAIN_CSV);
    match end.recording {
        Ok(mut r) => {
            r.csv = csv;
            Ok(format!("{r}{clock}"))
        }
        Err(mut e) => {
            e.csv = csv;
            crate::bail!("the servo recording is complete in the trial {trial}, but {e}{clock}")
        }
    }
}

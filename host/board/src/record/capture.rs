//! The recording loop: telemetry from a board into a [`Recorder`] until a time on the board's clock
//! has passed, the robot stands again, or the caller asks it to end (Ctrl-C).

use std::time::Duration;

use protocol::RunState;

use super::csv_out::Recorder;
use crate::link::{Board, LinkError, Transport};

/// When a recording ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Until {
    /// Seconds of board time after the first record.
    pub seconds: Option<f64>,
    /// End when the board is standing (or idle) again after it was seen moving.
    pub standing: bool,
}

/// Why a recording stopped early.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CaptureError {
    /// The link failed; every record received before is in the CSV.
    #[error("{source}; the CSV keeps the {cycles} bus cycles received before")]
    Link {
        #[source]
        source: LinkError,
        cycles: usize,
    },
    #[error("writing the CSV: {0}")]
    Write(#[from] std::io::Error),
    #[error("no telemetry for {seconds} s (is telemetry off, or is the board not walking?)")]
    Silent { seconds: f64 },
}

/// How often the loop asks the board for its state when `until.standing`, s of board time.
const STATE_POLL_S: f64 = 0.2;
/// Silence after which the board is taken not to be sending telemetry, s of board time.
const SILENCE_S: f64 = 2.0;

/// How a recording ended without error.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ended {
    /// As [`Until`] asked.
    Done,
    /// The caller's `interrupted` turned true; the board was left as it was.
    Interrupted,
}

/// Records telemetry of `board` into `rec`; `progress(seconds_recorded)` after each record.
pub fn capture<T: Transport>(
    board: &mut Board<T>,
    rec: &mut Recorder,
    until: Until,
    progress: impl FnMut(f64),
) -> Result<(), CaptureError> {
    capture_while(board, rec, until, || false, progress).map(|_| ())
}

/// [`capture`] that also ends as soon as `interrupted()` is true (checked before every record), so
/// that a Ctrl-C handler can end a recording between two whole rows.
pub fn capture_while<T: Transport>(
    board: &mut Board<T>,
    rec: &mut Recorder,
    until: Until,
    mut interrupted: impl FnMut() -> bool,
    mut progress: impl FnMut(f64),
) -> Result<Ended, CaptureError> {
    let link = |source, rec: &Recorder| CaptureError::Link {
        source,
        cycles: rec.cycles(),
    };
    let mut moving = false;
    let mut next_poll = 0.0;
    loop {
        if interrupted() {
            return Ok(Ended::Interrupted);
        }
        let t = match board.telemetry(Duration::from_secs_f64(SILENCE_S)) {
            Ok(Some(t)) => t,
            Ok(None) if moving || until.standing => {
                // Nothing comes while standing: check whether the walk has ended.
                let st = board.status().map_err(|e| link(e, rec))?;
                if matches!(st.state, RunState::Standing | RunState::Idle) {
                    return Ok(Ended::Done);
                }
                return Err(CaptureError::Silent { seconds: SILENCE_S });
            }
            Ok(None) => return Err(CaptureError::Silent { seconds: SILENCE_S }),
            Err(e) => return Err(link(e, rec)),
        };
        rec.push(&t)?;
        let elapsed = rec.duration_s();
        progress(elapsed);
        if until.seconds.is_some_and(|s| elapsed >= s) {
            return Ok(Ended::Done);
        }
        if until.standing && elapsed >= next_poll {
            next_poll = elapsed + STATE_POLL_S;
            let st = board.status().map_err(|e| link(e, rec))?;
            match st.state {
                RunState::Ramping | RunState::Walking | RunState::Stopping => moving = true,
                RunState::Standing | RunState::Idle if moving => return Ok(Ended::Done),
                RunState::Fault => return Ok(Ended::Done),
                _ => {}
            }
        }
    }
}

//! The recording loop: telemetry from a board into a [`Recorder`] until a time on the board's clock
//! has passed or the robot stands again.

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

/// Records telemetry of `board` into `rec`; `progress(seconds_recorded)` after each record.
pub fn capture<T: Transport>(
    board: &mut Board<T>,
    rec: &mut Recorder,
    until: Until,
    mut progress: impl FnMut(f64),
) -> Result<(), CaptureError> {
    let link = |source, rec: &Recorder| CaptureError::Link {
        source,
        cycles: rec.cycles(),
    };
    let mut moving = false;
    let mut next_poll = 0.0;
    loop {
        let t = match board.telemetry(Duration::from_secs_f64(SILENCE_S)) {
            Ok(Some(t)) => t,
            Ok(None) if moving || until.standing => {
                // Nothing comes while standing: check whether the walk has ended.
                let st = board.status().map_err(|e| link(e, rec))?;
                if matches!(st.state, RunState::Standing | RunState::Idle) {
                    return Ok(());
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
            return Ok(());
        }
        if until.standing && elapsed >= next_poll {
            next_poll = elapsed + STATE_POLL_S;
            let st = board.status().map_err(|e| link(e, rec))?;
            match st.state {
                RunState::Ramping | RunState::Walking | RunState::Stopping => moving = true,
                RunState::Standing | RunState::Idle if moving => return Ok(()),
                RunState::Fault => return Ok(()),
                _ => {}
            }
        }
    }
}

//! The recording loop: telemetry from a board into a [`Recorder`] until a time on the board's clock
//! has passed, the robot stands again, the board stops it on a fault, or the caller asks it to
//! end (Ctrl-C).

use std::time::Duration;

use protocol::{Fault, RunState};

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
    #[error(
        "telemetry every {every} bus cycles at {cycle_hz} Hz is one record per {interval_s:.2} s, \
         and a recording takes {silence_s} s without telemetry for a board that stopped sending: \
         give at most {max_every} cycles"
    )]
    RateTooLow {
        every: u16,
        cycle_hz: u16,
        interval_s: f64,
        silence_s: f64,
        max_every: u64,
    },
}

/// Refuses a telemetry rate (a record every `every` bus cycles at `cycle_hz`) that the silence
/// limit of [`capture_while`] cannot serve: a recording of it would end after its first gap.
pub fn check_telemetry_rate(every: u16, cycle_hz: u16) -> Result<(), CaptureError> {
    let hz = f64::from(cycle_hz.max(1));
    let interval_s = f64::from(every) / hz;
    // The longest interval that still leaves a whole bus cycle of margin before the limit.
    let max_every = ((SILENCE_S * hz).floor() as u64).saturating_sub(1).max(1);
    if u64::from(every) > max_every {
        return Err(CaptureError::RateTooLow {
            every,
            cycle_hz,
            interval_s,
            silence_s: SILENCE_S,
            max_every,
        });
    }
    Ok(())
}

/// Checks `every` against the board's bus cycle rate ([`check_telemetry_rate`]), then asks the
/// board for telemetry every `every` cycles.
pub fn set_recording_rate<T: Transport>(
    board: &mut Board<T>,
    every: u16,
) -> Result<(), CaptureError> {
    let link = |source| CaptureError::Link { source, cycles: 0 };
    let hz = board.settings().map_err(link)?.cycle_hz;
    check_telemetry_rate(every, hz)?;
    board.set_telemetry(every).map_err(link)
}

/// Records until the board stands after it was asked to stop ([`super::stop_walk`]): its state
/// is read at once, not only after it was seen moving (a ramp that was stopped stands at once).
pub fn capture_until_standing<T: Transport>(
    board: &mut Board<T>,
    rec: &mut Recorder,
    progress: impl FnMut(f64),
) -> Result<Ended, CaptureError> {
    run(
        board,
        rec,
        Until {
            seconds: None,
            standing: true,
        },
        true,
        || false,
        progress,
    )
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
    /// The board stopped the robot on a fault: every record up to the first one in the fault
    /// state is in the recording.
    Faulted(FaultSeen),
}

/// A fault that ended a recording.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FaultSeen {
    /// The board's fault (`GetStatus`); `None` if it was cleared before the host asked.
    pub fault: Option<Fault>,
    /// The bus cycle of the first record in the fault state; `None` when the fault was seen by
    /// asking the board's state (no record carried it).
    pub cycle: Option<u32>,
}

impl std::fmt::Display for FaultSeen {
    /// `the board stopped the robot on a fault: ServoStuck on joint 2: ... (first seen in bus
    /// cycle 812)`
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "the board stopped the robot on a fault: ")?;
        match &self.fault {
            Some(fault) => write!(f, "{fault}")?,
            None => write!(f, "(cleared before it could be read)")?,
        }
        if let Some(c) = self.cycle {
            write!(f, " (first seen in bus cycle {c})")?;
        }
        Ok(())
    }
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
    interrupted: impl FnMut() -> bool,
    progress: impl FnMut(f64),
) -> Result<Ended, CaptureError> {
    run(board, rec, until, false, interrupted, progress)
}

/// The loop of [`capture_while`] and [`capture_until_standing`]; `moving`: the board is known to
/// have moved (so standing ends the recording at the first look).
fn run<T: Transport>(
    board: &mut Board<T>,
    rec: &mut Recorder,
    until: Until,
    mut moving: bool,
    mut interrupted: impl FnMut() -> bool,
    mut progress: impl FnMut(f64),
) -> Result<Ended, CaptureError> {
    let link = |source, rec: &Recorder| CaptureError::Link {
        source,
        cycles: rec.cycles(),
    };
    let mut next_poll = 0.0;
    // The fault as the board names it, with the cycle it was first seen in.
    let faulted = |board: &mut Board<T>, rec: &Recorder, cycle| {
        let st = board.status().map_err(|e| link(e, rec))?;
        Ok(Ended::Faulted(FaultSeen {
            fault: st.fault,
            cycle,
        }))
    };
    loop {
        if interrupted() {
            return Ok(Ended::Interrupted);
        }
        let t = match board.telemetry(Duration::from_secs_f64(SILENCE_S)) {
            Ok(Some(t)) => t,
            Ok(None) if moving || until.standing => {
                // Nothing comes while standing: check whether the walk has ended.
                let st = board.status().map_err(|e| link(e, rec))?;
                match st.state {
                    RunState::Standing | RunState::Idle => return Ok(Ended::Done),
                    RunState::Fault => return faulted(board, rec, None),
                    _ => return Err(CaptureError::Silent { seconds: SILENCE_S }),
                }
            }
            Ok(None) => return Err(CaptureError::Silent { seconds: SILENCE_S }),
            Err(e) => return Err(link(e, rec)),
        };
        rec.push(&t)?;
        let elapsed = rec.duration_s();
        progress(elapsed);
        if t.state == RunState::Fault {
            return faulted(board, rec, Some(t.cycle));
        }
        if until.seconds.is_some_and(|s| elapsed >= s) {
            return Ok(Ended::Done);
        }
        if until.standing && elapsed >= next_poll {
            next_poll = elapsed + STATE_POLL_S;
            let st = board.status().map_err(|e| link(e, rec))?;
            match st.state {
                RunState::Ramping | RunState::Walking | RunState::Stopping => moving = true,
                RunState::Standing | RunState::Idle if moving => return Ok(Ended::Done),
                RunState::Fault => return faulted(board, rec, None),
                _ => {}
            }
        }
    }
}

//! The strain board's calibration handshake as a state machine over the lines it prints:
//! Waiting (banner seen, start byte sent) -> Calibrating (per-leg progress) -> Done. A broken gauge
//! ends it for good (the board stops); a gauge that will not calibrate is noted with its final
//! value and calibration goes on. Pure: the driver feeds it lines and keeps the clock.

use super::channels::Channel;
use super::error::StrainError;
use super::line::BoardLine;

/// A gauge the board could not trim into 300 +- 75 counts.
#[derive(Debug, Clone, PartialEq)]
pub struct NotCalibrated {
    pub channel: Channel,
    /// The board's `Final value:` (None if it never printed one before `Done.`).
    pub final_value: Option<f64>,
}

/// What a finished calibration found.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CalibrationReport {
    pub not_calibrated: Vec<NotCalibrated>,
}

/// Where the handshake is.
#[derive(Debug, Clone, PartialEq)]
pub enum Phase {
    /// The banner was seen and the start byte sent; `Starting calibration.` is next.
    Waiting,
    /// Trimming gauges; `legs_done` legs have printed `Leg<N> complete.`.
    Calibrating {
        legs_done: usize,
        awaiting_final: Option<Channel>,
    },
    /// `Done.`: the board streams next.
    Done,
}

/// The handshake: its phase and what it has found so far.
#[derive(Debug, Clone, PartialEq)]
pub struct Calibration {
    pub phase: Phase,
    pub report: CalibrationReport,
}

impl Default for Calibration {
    fn default() -> Self {
        Self {
            phase: Phase::Waiting,
            report: CalibrationReport::default(),
        }
    }
}

impl Calibration {
    /// Legs complete so far (for a timeout's message).
    pub fn legs_done(&self) -> usize {
        match self.phase {
            Phase::Waiting => 0,
            Phase::Calibrating { legs_done, .. } => legs_done,
            Phase::Done => 6,
        }
    }

    /// Takes line `line_no` of `port`, read as `line` (its text is `text`, for messages).
    pub fn feed(
        &mut self,
        line: &BoardLine,
        text: &str,
        port: &str,
        line_no: u64,
    ) -> Result<&Phase, StrainError> {
        let out_of_place = |during| StrainError::OutOfPlace {
            port: port.to_owned(),
            line: line_no,
            text: text.trim().to_owned(),
            during,
        };
        let next = match (self.phase.clone(), line) {
            (Phase::Waiting, BoardLine::Banner) => Phase::Waiting,
            (Phase::Waiting, BoardLine::Starting) => Phase::Calibrating {
                legs_done: 0,
                awaiting_final: None,
            },
            (
                Phase::Waiting,
                BoardLine::Progress
                | BoardLine::LegComplete(_)
                | BoardLine::Broken(_)
                | BoardLine::WillNotCalibrate(_)
                | BoardLine::FinalValue(_)
                | BoardLine::Done
                | BoardLine::Sample(_),
            ) => return Err(out_of_place("waiting for `Starting calibration.`")),
            (Phase::Calibrating { .. }, BoardLine::Banner) => {
                return Err(StrainError::Reset {
                    port: port.to_owned(),
                    line: line_no,
                    samples: 0,
                });
            }
            (Phase::Calibrating { .. }, BoardLine::Broken(channel)) => {
                return Err(StrainError::Broken {
                    port: port.to_owned(),
                    channel: *channel,
                });
            }
            (
                Phase::Calibrating {
                    legs_done,
                    awaiting_final,
                },
                BoardLine::Progress,
            ) => Phase::Calibrating {
                legs_done,
                awaiting_final,
            },
            (Phase::Calibrating { legs_done, .. }, BoardLine::LegComplete(n)) => {
                if *n != legs_done {
                    return Err(out_of_place("calibrating (legs complete out of order)"));
                }
                self.flush_awaiting();
                Phase::Calibrating {
                    legs_done: n + 1,
                    awaiting_final: None,
                }
            }
            (Phase::Calibrating { legs_done, .. }, BoardLine::WillNotCalibrate(channel)) => {
                self.flush_awaiting();
                Phase::Calibrating {
                    legs_done,
                    awaiting_final: Some(*channel),
                }
            }
            (
                Phase::Calibrating {
                    legs_done,
                    awaiting_final: Some(channel),
                },
                BoardLine::FinalValue(v),
            ) => {
                self.report.not_calibrated.push(NotCalibrated {
                    channel,
                    final_value: Some(*v),
                });
                Phase::Calibrating {
                    legs_done,
                    awaiting_final: None,
                }
            }
            (
                Phase::Calibrating {
                    awaiting_final: None,
                    ..
                },
                BoardLine::FinalValue(_),
            ) => return Err(out_of_place("calibrating (a final value with no gauge)")),
            (Phase::Calibrating { .. }, BoardLine::Done) => {
                self.flush_awaiting();
                Phase::Done
            }
            (Phase::Calibrating { .. }, BoardLine::Starting | BoardLine::Sample(_)) => {
                return Err(out_of_place("calibrating"));
            }
            (Phase::Done, _) => return Err(out_of_place("streaming (calibration is over)")),
        };
        self.phase = next;
        Ok(&self.phase)
    }

    /// A will-not-calibrate gauge whose final value never came is kept without one.
    fn flush_awaiting(&mut self) {
        if let Phase::Calibrating {
            awaiting_final: Some(channel),
            ..
        } = self.phase
        {
            self.report.not_calibrated.push(NotCalibrated {
                channel,
                final_value: None,
            });
        }
    }
}

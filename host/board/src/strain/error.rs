//! What can go wrong with the strain board, each error naming the port and, where there is one,
//! the line and the leg and gauge.

use super::channels::Channel;

/// A line the board sent that is not what the protocol allows.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{port} line {line}: {problem}")]
pub struct LineError {
    pub port: String,
    /// 1-based, counted from when the port was opened.
    pub line: u64,
    pub problem: LineProblem,
}

/// What is wrong with a line.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum LineProblem {
    #[error("{0} numbers where the strain board sends 36")]
    Count(usize),
    #[error("column {}, {}: `{text}` is not a number", channel.column() + 1, channel.describe())]
    NotANumber { channel: Channel, text: String },
    #[error(
        "column {}, {}: {value} is outside the board's 0..1023 counts",
        channel.column() + 1,
        channel.describe()
    )]
    OutOfRange { channel: Channel, value: f64 },
    #[error("not a line of the strain board: `{0}`")]
    Unknown(String),
}

/// What came from a port that never printed the strain board's banner.
#[derive(Debug, Clone, PartialEq)]
pub enum Heard {
    Nothing,
    /// Bytes that are not text (NUL, other control bytes): framed binary, as the servo board's
    /// link speaks.
    Binary {
        bytes: usize,
    },
    /// Text lines, none of them the banner; the first one.
    Text {
        first: String,
    },
    /// Sample lines: the board was already streaming (it did not reset when the port opened).
    Samples,
}

impl std::fmt::Display for Heard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Heard::Nothing => write!(
                f,
                "it sent nothing (the servo board also stays silent until asked; is this the \
                 strain board's port?)"
            ),
            Heard::Binary { bytes } => write!(
                f,
                "it sent {bytes} bytes of binary data, not text lines: this looks like the servo \
                 board's link, not the strain board"
            ),
            Heard::Text { first } => write!(f, "it sent text that is not the banner: `{first}`"),
            Heard::Samples => write!(
                f,
                "it is streaming samples already (it did not reset when the port opened); press \
                 the strain board's reset button and try again"
            ),
        }
    }
}

/// Errors of the strain board driver.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StrainError {
    #[error("{port}: cannot open the strain board's port: {source}")]
    Open {
        port: String,
        source: std::io::Error,
    },
    #[error("{port}: reading or writing the strain board failed: {source}")]
    Io {
        port: String,
        source: std::io::Error,
    },
    #[error("{port}: the strain board went away (unplugged?) after {samples} samples")]
    Closed { port: String, samples: u64 },
    #[error("{port}: no `Waiting on MATLAB...` banner within {waited_s} s: {heard}")]
    NoBanner {
        port: String,
        waited_s: f64,
        heard: Heard,
    },
    #[error(transparent)]
    Line(#[from] LineError),
    #[error(
        "{port}: calibration stopped for good: gauge {} is broken or unplugged; check its cable \
         and reset the board",
        channel.describe()
    )]
    Broken { port: String, channel: Channel },
    #[error(
        "{port}: the strain board did not say `Done.` within {waited_s} s of calibrating \
         ({legs_done} of 6 legs complete)"
    )]
    CalibrationTimeout {
        port: String,
        waited_s: f64,
        legs_done: usize,
    },
    #[error("{port} line {line}: `{text}` out of place while {during}")]
    OutOfPlace {
        port: String,
        line: u64,
        text: String,
        during: &'static str,
    },
    #[error(
        "{port} line {line}: the strain board reset (its banner came again) after {samples} \
         samples; its calibration is lost"
    )]
    Reset {
        port: String,
        line: u64,
        samples: u64,
    },
    #[error("{port}: no sample from the strain board within {waited_s} s")]
    NoSample { port: String, waited_s: f64 },
    #[error("cannot write {path}: {source}")]
    File {
        path: String,
        source: std::io::Error,
    },
    #[error(
        "{port} is the servo board's port; the strain board has a port of its own (`dbot devices` \
         lists the servo board)"
    )]
    ServoPort { port: String },
}

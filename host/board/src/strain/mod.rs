//! The lab's 36-channel strain board (see `../shared/reference/lab-practice.md`): its channel
//! table, the line parser, the calibration handshake, the driver, the recorder that runs beside a
//! servo recording, and a virtual board that speaks the same protocol (in process or on a
//! pseudo-terminal).

pub mod baseline;
pub mod beside;
pub mod calibration;
pub mod channels;
pub mod check;
pub mod clock;
pub mod driver;
pub mod error;
pub mod line;
pub mod port;
pub mod pty;
pub mod recorder;
pub mod source;
pub mod stats;
pub mod virtual_board;

pub use beside::{StrainBeside, StrainEnd};
pub use calibration::{CalibrationReport, NotCalibrated};
pub use channels::{Channel, GaugeKind};
pub use driver::{Sample, StrainBoard, Timeouts};
pub use error::{Heard, LineError, LineProblem, StrainError};
pub use recorder::{StrainRecordError, StrainRecorder, StrainRecording};
pub use source::{Reading, StrainSource};
pub use virtual_board::{Fault, VirtualStrainBoard};

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_beside;

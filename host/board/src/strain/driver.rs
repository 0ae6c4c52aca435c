//! The host's end of the strain board: waits for its banner, runs the calibration handshake,
//! starts and stops the stream and reads samples, each stamped with the host clock when its line
//! ended. Generic over `std::io::{Read, Write}`; reads must time out (return `TimedOut` or
//! `WouldBlock` when nothing came, as a serial port with a timeout does) for the deadlines to hold.
//!
//! Time stamps: the board sends none. A sample is stamped with the host's `Instant` at which the
//! read that completed its line (its LF) returned. The board reads its channels as it prints them,
//! so the true reading of a channel lies up to one line time before the stamp: a line is about
//! 36 x 7 + 2 = 254 characters, 254 x 10 bit / 115200 bit/s = 22.0 ms (estimate; 25.2 ms if every
//! value has four digits), plus the USB-serial bridge's latency (estimate: at most 2 ms), so the
//! stamp is late by 0 to about 24 ms. Samples come about every 24 ms (a line plus the board's 2 ms
//! pause; estimate, about 41 Hz).

use std::collections::VecDeque;
use std::io::{ErrorKind, Read, Write};
use std::time::{Duration, Instant};

use super::calibration::{Calibration, CalibrationReport, Phase};
use super::error::{Heard, StrainError};
use super::line::{self, BoardLine, Counts};

/// The strain board's line rate.
pub const STRAIN_BAUD: u32 = 115_200;

/// How long the driver waits for each stage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Timeouts {
    /// For the banner after opening the port (an Arduino Mega resets when the port opens and its
    /// bootloader takes about 2 s).
    pub banner: Duration,
    /// For `Done.` after the start byte.
    pub calibration: Duration,
    /// For each sample while streaming.
    pub sample: Duration,
}

impl Default for Timeouts {
    fn default() -> Self {
        Self {
            banner: Duration::from_secs(5),
            calibration: Duration::from_secs(120),
            sample: Duration::from_secs(1),
        }
    }
}

/// One sample: 36 raw counts, the host instant its line ended, its line number.
#[derive(Debug, Clone, PartialEq)]
pub struct Sample {
    pub counts: Counts,
    pub host: Instant,
    pub line: u64,
}

/// A strain board on `io`.
#[derive(Debug)]
pub struct StrainBoard<T> {
    io: T,
    port: String,
    partial: Vec<u8>,
    lines: VecDeque<(String, Instant)>,
    line_no: u64,
    samples: u64,
    binary_bytes: usize,
    timeouts: Timeouts,
}

/// Opens the strain board's serial port `path` at 115200 bit/s.
pub fn open_serial(path: &str) -> Result<Box<dyn serialport::SerialPort>, StrainError> {
    let open_err = |source| StrainError::Open {
        port: path.to_owned(),
        source,
    };
    if let Some(e) = crate::link::not_a_port(path) {
        return Err(open_err(e));
    }
    serialport::new(path, STRAIN_BAUD)
        .timeout(Duration::from_millis(20))
        .open()
        .map_err(|e| open_err(crate::link::explain_open_error(path, e)))
}

impl<T: Read + Write> StrainBoard<T> {
    /// The board on `io`, named `port` in every message.
    pub fn new(io: T, port: impl Into<String>, timeouts: Timeouts) -> Self {
        Self {
            io,
            port: port.into(),
            partial: Vec::new(),
            lines: VecDeque::new(),
            line_no: 0,
            samples: 0,
            binary_bytes: 0,
            timeouts,
        }
    }

    pub fn port(&self) -> &str {
        &self.port
    }

    /// Samples read so far.
    pub fn samples(&self) -> u64 {
        self.samples
    }

    /// Waits for the banner, sends the start byte and follows the calibration to `Done.`; the
    /// board streams from then on.
    pub fn calibrate(&mut self) -> Result<CalibrationReport, StrainError> {
        self.wait_banner()?;
        self.send(1)?;
        let deadline = Instant::now() + self.timeouts.calibration;
        let mut cal = Calibration::default();
        loop {
            let Some((text, _)) = self.next_line(deadline)? else {
                return Err(StrainError::CalibrationTimeout {
                    port: self.port.clone(),
                    waited_s: self.timeouts.calibration.as_secs_f64(),
                    legs_done: cal.legs_done(),
                });
            };
            let parsed = line::parse(&text, &self.port, self.line_no)?;
            match cal.feed(&parsed, &text, &self.port, self.line_no)? {
                Phase::Done => return Ok(cal.report),
                Phase::Waiting | Phase::Calibrating { .. } => {}
            }
        }
    }

    /// Reads lines until the banner; says what came instead if it does not.
    fn wait_banner(&mut self) -> Result<(), StrainError> {
        let deadline = Instant::now() + self.timeouts.banner;
        let mut heard = Heard::Nothing;
        while let Some((text, _)) = self.next_line(deadline)? {
            match line::parse(&text, &self.port, self.line_no) {
                Ok(BoardLine::Banner) => return Ok(()),
                Ok(BoardLine::Sample(_)) => heard = Heard::Samples,
                Ok(_) | Err(_) if matches!(heard, Heard::Nothing) => {
                    heard = Heard::Text {
                        first: text.trim().chars().take(60).collect(),
                    }
                }
                Ok(_) | Err(_) => {}
            }
        }
        if self.binary_bytes > 0 && !matches!(heard, Heard::Samples) {
            heard = Heard::Binary {
                bytes: self.binary_bytes,
            };
        }
        Err(StrainError::NoBanner {
            port: self.port.clone(),
            waited_s: self.timeouts.banner.as_secs_f64(),
            heard,
        })
    }

    /// The next sample. A banner means the board reset; any other line is refused.
    pub fn next_sample(&mut self) -> Result<Sample, StrainError> {
        let deadline = Instant::now() + self.timeouts.sample;
        let Some((text, host)) = self.next_line(deadline)? else {
            return Err(StrainError::NoSample {
                port: self.port.clone(),
                waited_s: self.timeouts.sample.as_secs_f64(),
            });
        };
        match line::parse(&text, &self.port, self.line_no)? {
            BoardLine::Sample(counts) => {
                self.samples += 1;
                Ok(Sample {
                    counts,
                    host,
                    line: self.line_no,
                })
            }
            BoardLine::Banner => Err(StrainError::Reset {
                port: self.port.clone(),
                line: self.line_no,
                samples: self.samples,
            }),
            BoardLine::Starting
            | BoardLine::Progress
            | BoardLine::LegComplete(_)
            | BoardLine::Broken(_)
            | BoardLine::WillNotCalibrate(_)
            | BoardLine::FinalValue(_)
            | BoardLine::Done => Err(StrainError::OutOfPlace {
                port: self.port.clone(),
                line: self.line_no,
                text: text.trim().to_owned(),
                during: "streaming",
            }),
        }
    }

    /// Stops the stream (a byte of value 0) and drops what was already on its way.
    pub fn stop(&mut self) -> Result<(), StrainError> {
        self.send(0)?;
        let until = Instant::now() + Duration::from_millis(200);
        let mut quiet_since = Instant::now();
        while Instant::now() < until && quiet_since.elapsed() < Duration::from_millis(60) {
            if self
                .next_line(Instant::now() + Duration::from_millis(10))?
                .is_some()
            {
                quiet_since = Instant::now();
            }
        }
        self.lines.clear();
        Ok(())
    }

    /// Starts the stream again (a non-zero byte).
    pub fn start(&mut self) -> Result<(), StrainError> {
        self.send(1)
    }

    fn send(&mut self, byte: u8) -> Result<(), StrainError> {
        self.io
            .write_all(&[byte])
            .and_then(|()| self.io.flush())
            .map_err(|e| self.io_error(e))
    }

    /// The next whole line (CR LF removed) and the instant it ended, or None at `deadline`.
    fn next_line(&mut self, deadline: Instant) -> Result<Option<(String, Instant)>, StrainError> {
        let mut buf = [0u8; 512];
        loop {
            if let Some(l) = self.lines.pop_front() {
                self.line_no += 1;
                return Ok(Some(l));
            }
            // The deadline is looked at only when a read brought nothing, so a board that is
            // talking is never cut off by a slow reader.
            let timed_out = || Instant::now() >= deadline;
            match self.io.read(&mut buf) {
                Ok(0) => {
                    return Err(StrainError::Closed {
                        port: self.port.clone(),
                        samples: self.samples,
                    });
                }
                Ok(n) => self.take(&buf[..n], Instant::now()),
                Err(e) if e.kind() == ErrorKind::Interrupted => {}
                Err(e) if e.kind() == ErrorKind::TimedOut => {
                    if timed_out() {
                        return Ok(None);
                    }
                }
                Err(e) if e.kind() == ErrorKind::WouldBlock => {
                    if timed_out() {
                        return Ok(None);
                    }
                    std::thread::sleep(Duration::from_millis(1));
                }
                Err(e) => return Err(self.io_error(e)),
            }
        }
    }

    /// Splits bytes into lines stamped `at`.
    fn take(&mut self, bytes: &[u8], at: Instant) {
        for &b in bytes {
            if b == b'\n' {
                let raw = std::mem::take(&mut self.partial);
                let text = String::from_utf8_lossy(&raw)
                    .trim_end_matches('\r')
                    .to_owned();
                self.lines.push_back((text, at));
            } else {
                if b != b'\r' && b != b'\t' && !(0x20..0x7f).contains(&b) {
                    self.binary_bytes += 1;
                }
                self.partial.push(b);
            }
        }
        // Binary data may never hold an LF: keep the buffer bounded (a strain line is < 300 B).
        if self.partial.len() > 4096 {
            let raw = std::mem::take(&mut self.partial);
            self.lines
                .push_back((String::from_utf8_lossy(&raw).into_owned(), at));
        }
    }

    fn io_error(&self, e: std::io::Error) -> StrainError {
        if crate::link::is_gone(&e) {
            StrainError::Closed {
                port: self.port.clone(),
                samples: self.samples,
            }
        } else {
            StrainError::Io {
                port: self.port.clone(),
                source: e,
            }
        }
    }
}

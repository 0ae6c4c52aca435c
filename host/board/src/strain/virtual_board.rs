//! A virtual strain board: the lab's board's protocol (banner, calibration messages, the
//! 36-value stream, start and stop bytes) over any `Read + Write`, fed by a [`StrainSource`],
//! with faults on demand. Reads must time out (return `TimedOut` or `WouldBlock` when nothing
//! came) so the board can stream and listen at once; end of file or a hang-up ends a session,
//! as unplugging the USB cable ends the real board's.
//!
//! Counts: every gauge is trimmed to [`BASELINE`] counts at calibration; a strain reading becomes
//! baseline + gain x strain (gain in counts per microstrain), rounded to a whole count (the ADC's)
//! and saturated to 0..1023.

use std::io::{ErrorKind, Read, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use super::channels::{self, Channel};
use super::line::{self, Counts, MAX_COUNT};
use super::source::{Reading, StrainSource};

/// Where calibration trims every gauge (the board aims at 300 +- 75).
pub const BASELINE: f64 = 300.0;
/// What a gauge that will not calibrate is left reading (outside 300 +- 75).
pub const UNCALIBRATED: f64 = 980.0;
/// Default gain, counts per microstrain (an invented value: the lab's gain is not published).
pub const DEFAULT_GAIN: f64 = 0.5;

/// A fault of the virtual board.
#[derive(Debug, Clone, PartialEq)]
pub enum Fault {
    /// The gauge reads 1023: calibration stops for good at it.
    Unplugged(Channel),
    /// The gauge cannot be trimmed: reported with [`UNCALIBRATED`] and streamed at it.
    NoCalibrate(Channel),
    /// Uniform noise of +- this many counts on every value (a fixed-seed generator).
    Noise(f64),
    /// After this many samples the board resets (prints its banner, waits, calibrates again).
    ResetAt(u64),
    /// After this many samples the board goes away (the session ends, as an unplugged cable).
    HangUpAt(u64),
    /// Sample number this many is sent with a garbled value in column 8 (`3?0.00`, as a noisy
    /// cable or a baud-rate slip prints), then streaming goes on.
    GarbageAt(u64),
    /// Calibration never prints `Done.` (the board goes silent after the last leg).
    NeverDone,
}

impl Fault {
    /// `unplugged:GAUGE`, `no-calibrate:GAUGE`, `noise:COUNTS`, `reset-at:SAMPLES`,
    /// `hangup-at:SAMPLES`, `garbage-at:SAMPLES` or `no-done`; the error is a sentence.
    pub fn parse(s: &str) -> Result<Fault, String> {
        let (kind, arg) = s.split_once(':').unwrap_or((s, ""));
        let gauge = || {
            Channel::parse(arg).ok_or_else(|| {
                format!(
                    "`{arg}` is not a gauge name (e.g. LF_troch_axial; legs LF LM LH RF RM RH, \
                     gauges {})",
                    channels::GaugeKind::ALL.map(|k| k.name()).join(" ")
                )
            })
        };
        let count = || {
            arg.parse::<u64>()
                .map_err(|_| format!("`{arg}` is not a whole number of samples"))
        };
        match kind {
            "unplugged" => gauge().map(Fault::Unplugged),
            "no-calibrate" => gauge().map(Fault::NoCalibrate),
            "noise" => arg
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && *v >= 0.0)
                .map(Fault::Noise)
                .ok_or_else(|| format!("`{arg}` is not a number of counts (0 or more)")),
            "reset-at" => count().map(Fault::ResetAt),
            "hangup-at" => count().map(Fault::HangUpAt),
            "garbage-at" => count().map(Fault::GarbageAt),
            "no-done" => Ok(Fault::NeverDone),
            _ => Err(format!(
                "`{s}`: faults are unplugged:GAUGE, no-calibrate:GAUGE, noise:COUNTS, \
                 reset-at:SAMPLES, hangup-at:SAMPLES, garbage-at:SAMPLES, no-done"
            )),
        }
    }
}

/// `line` with its eighth value's second character replaced by `?`.
fn garble(line: &str) -> String {
    line.split(' ')
        .enumerate()
        .map(|(i, v)| {
            if i == 7 && v.len() > 1 {
                format!("{}?{}", &v[..1], &v[2..])
            } else {
                v.to_owned()
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// How a session ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Ended {
    /// `stop` was set.
    Stopped,
    /// The host closed its end.
    HostGone,
    /// The [`Fault::HangUpAt`] fault ended it after this many samples.
    HungUp(u64),
}

/// The virtual board.
pub struct VirtualStrainBoard {
    source: Box<dyn StrainSource>,
    faults: Vec<Fault>,
    gain: f64,
    /// Wait the wire time of each line and the board's 2 ms pause (false: as fast as the reader).
    paced: bool,
    rng: u64,
}

impl std::fmt::Debug for VirtualStrainBoard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("VirtualStrainBoard")
            .field("faults", &self.faults)
            .field("gain", &self.gain)
            .field("paced", &self.paced)
            .finish_non_exhaustive()
    }
}

/// What one call to [`VirtualStrainBoard::serve`] does next.
enum Next {
    Go,
    End(Ended),
}

impl VirtualStrainBoard {
    pub fn new(source: Box<dyn StrainSource>, faults: Vec<Fault>, paced: bool) -> Self {
        Self {
            source,
            faults,
            gain: DEFAULT_GAIN,
            paced,
            rng: 0x2545_f491_4f6c_dd1d,
        }
    }

    /// Counts per microstrain.
    pub fn with_gain(mut self, gain: f64) -> Self {
        self.gain = gain;
        self
    }

    /// One session, from power-on (the banner) until the host goes away or `stop` is set.
    pub fn serve<T: Read + Write>(
        &mut self,
        io: &mut T,
        stop: &AtomicBool,
    ) -> std::io::Result<Ended> {
        let mut sent: u64 = 0;
        loop {
            // Power-on or reset.
            if let Next::End(e) = self.say(io, line::BANNER) {
                return Ok(e);
            }
            match self.wait_start(io, stop)? {
                Next::Go => {}
                Next::End(e) => return Ok(e),
            }
            match self.calibrate(io, stop)? {
                Next::Go => {}
                Next::End(e) => return Ok(e),
            }
            match self.stream(io, stop, &mut sent)? {
                Next::Go => continue, // a reset: the banner again
                Next::End(e) => return Ok(e),
            }
        }
    }

    /// Waits for a non-zero byte.
    fn wait_start<T: Read + Write>(
        &mut self,
        io: &mut T,
        stop: &AtomicBool,
    ) -> std::io::Result<Next> {
        loop {
            if stop.load(Ordering::Relaxed) {
                return Ok(Next::End(Ended::Stopped));
            }
            match input(io) {
                Input::Byte(b) if b != 0 => return Ok(Next::Go),
                Input::Byte(_) | Input::Nothing => {}
                Input::Gone => return Ok(Next::End(Ended::HostGone)),
            }
        }
    }

    fn calibrate<T: Read + Write>(
        &mut self,
        io: &mut T,
        stop: &AtomicBool,
    ) -> std::io::Result<Next> {
        if let Next::End(e) = self.say(io, "Starting calibration.") {
            return Ok(Next::End(e));
        }
        for leg in 0..6 {
            for gauge in 0..channels::GAUGES_PER_LEG {
                let ch = Channel::on_board(leg, gauge).expect("6 x 6");
                let mut lines = vec![gauge.to_string()];
                if self.faults.contains(&Fault::Unplugged(ch)) {
                    lines.push(format!(
                        "Gauge {gauge} on leg {leg} is broken or unplugged. Please check the cable."
                    ));
                    for l in lines {
                        if let Next::End(e) = self.say(io, &l) {
                            return Ok(Next::End(e));
                        }
                    }
                    return self.halt(io, stop);
                }
                if self.faults.contains(&Fault::NoCalibrate(ch)) {
                    lines.push(format!(
                        "Gauge {gauge} on leg {leg} will not calibrate. Please check the cable and board."
                    ));
                    lines.push(format!("Final value: {UNCALIBRATED:.0}"));
                }
                for l in lines {
                    if let Next::End(e) = self.say(io, &l) {
                        return Ok(Next::End(e));
                    }
                }
            }
            if let Next::End(e) = self.say(io, &format!("Leg{leg} complete.")) {
                return Ok(Next::End(e));
            }
        }
        if self.faults.contains(&Fault::NeverDone) {
            return self.halt(io, stop);
        }
        Ok(match self.say(io, line::DONE) {
            Next::Go => Next::Go,
            Next::End(e) => Next::End(e),
        })
    }

    /// Stopped for good (a broken gauge): silent until the host goes away.
    fn halt<T: Read + Write>(&mut self, io: &mut T, stop: &AtomicBool) -> std::io::Result<Next> {
        loop {
            if stop.load(Ordering::Relaxed) {
                return Ok(Next::End(Ended::Stopped));
            }
            if let Input::Gone = input(io) {
                return Ok(Next::End(Ended::HostGone));
            }
        }
    }

    /// Streams while the last byte was non-zero; `Go` means the board reset.
    fn stream<T: Read + Write>(
        &mut self,
        io: &mut T,
        stop: &AtomicBool,
        sent: &mut u64,
    ) -> std::io::Result<Next> {
        let mut on = true;
        let mut t_s = 0.0;
        loop {
            if stop.load(Ordering::Relaxed) {
                return Ok(Next::End(Ended::Stopped));
            }
            match input(io) {
                Input::Byte(b) => on = b != 0,
                Input::Nothing => {}
                Input::Gone => return Ok(Next::End(Ended::HostGone)),
            }
            if !on {
                continue;
            }
            if self.faults.contains(&Fault::HangUpAt(*sent)) {
                return Ok(Next::End(Ended::HungUp(*sent)));
            }
            if self.faults.contains(&Fault::ResetAt(*sent)) {
                // Counted once: a reset does not reset the fault's sample count.
                *sent += 1;
                return Ok(Next::Go);
            }
            let counts = self.counts(*sent, t_s);
            let mut text = line::format_sample(&counts);
            if self.faults.contains(&Fault::GarbageAt(*sent)) {
                text = garble(&text);
            }
            if let Next::End(e) = self.say(io, &text) {
                return Ok(Next::End(e));
            }
            t_s += line_period(text.len() + 2).as_secs_f64();
            *sent += 1;
            if self.paced {
                std::thread::sleep(Duration::from_millis(2));
            }
        }
    }

    fn counts(&mut self, k: u64, t_s: f64) -> Counts {
        let mut out = match self.source.reading(k, t_s) {
            Reading::Counts(c) => c,
            Reading::Microstrain(s) => s.map(|e| BASELINE + self.gain * e),
        };
        for (c, v) in out.iter_mut().enumerate() {
            let ch = Channel::at_column(c).expect("36 columns");
            if self.faults.contains(&Fault::NoCalibrate(ch)) {
                *v += UNCALIBRATED - BASELINE;
            }
        }
        let noise = self.faults.iter().find_map(|f| match f {
            Fault::Noise(n) => Some(*n),
            Fault::Unplugged(_)
            | Fault::NoCalibrate(_)
            | Fault::ResetAt(_)
            | Fault::HangUpAt(_)
            | Fault::GarbageAt(_)
            | Fault::NeverDone => None,
        });
        for v in out.iter_mut() {
            if let Some(n) = noise {
                *v += n * (2.0 * self.uniform() - 1.0);
            }
            *v = v.round().clamp(0.0, MAX_COUNT);
        }
        out
    }

    /// xorshift64*: a fixed-seed uniform number in [0, 1).
    fn uniform(&mut self) -> f64 {
        self.rng ^= self.rng >> 12;
        self.rng ^= self.rng << 25;
        self.rng ^= self.rng >> 27;
        (self.rng.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Writes a line with CR LF, at wire speed if paced.
    fn say<T: Write>(&mut self, io: &mut T, text: &str) -> Next {
        let bytes = format!("{text}\r\n");
        if io
            .write_all(bytes.as_bytes())
            .and_then(|()| io.flush())
            .is_err()
        {
            return Next::End(Ended::HostGone);
        }
        if self.paced {
            std::thread::sleep(wire_time(bytes.len()));
        }
        Next::Go
    }
}

/// Time `bytes` take on the board's line: 10 bits per byte (8N1) at 115200 bit/s.
pub fn wire_time(bytes: usize) -> Duration {
    Duration::from_nanos(bytes as u64 * 10 * 1_000_000_000 / super::driver::STRAIN_BAUD as u64)
}

/// Sample period for a line of `bytes` bytes: its wire time plus the board's 2 ms pause.
pub fn line_period(bytes: usize) -> Duration {
    wire_time(bytes) + Duration::from_millis(2)
}

enum Input {
    Byte(u8),
    Nothing,
    Gone,
}

/// The last byte the host sent since the last look, if any.
fn input<T: Read>(io: &mut T) -> Input {
    let mut buf = [0u8; 64];
    match io.read(&mut buf) {
        Ok(0) => Input::Gone,
        Ok(n) => Input::Byte(buf[n - 1]),
        Err(e) if matches!(e.kind(), ErrorKind::TimedOut | ErrorKind::Interrupted) => {
            Input::Nothing
        }
        Err(e) if e.kind() == ErrorKind::WouldBlock => {
            std::thread::sleep(Duration::from_millis(1));
            Input::Nothing
        }
        Err(_) => Input::Gone,
    }
}

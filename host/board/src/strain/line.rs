//! One line from the strain board, read as what it means: the reset banner, a calibration
//! message, or a sample of 36 raw counts. The words are the board's (see
//! `../shared/reference/lab-practice.md`); a line that is none of them is refused with the port,
//! the line number and, for a bad number, the column's leg and gauge.
//!
//! The board numbers legs and gauges from 0 (`Leg<N> complete.` with N = 0..5); its broken and
//! will-not-calibrate messages are read with the same numbering.

use super::channels::{CHANNELS, Channel};
use super::error::{LineError, LineProblem};

/// The banner the board prints after a reset.
pub const BANNER: &str = "Waiting on MATLAB...";
/// The first line of calibration.
pub const STARTING: &str = "Starting calibration.";
/// The last line of calibration.
pub const DONE: &str = "Done.";
/// Largest raw count (10-bit ADC).
pub const MAX_COUNT: f64 = 1023.0;

/// 36 raw counts, in column order ([`Channel::at_column`]).
pub type Counts = [f64; CHANNELS];

/// What a line says. (Samples are nearly every line the board sends: kept inline rather than
/// boxed, so a sample costs no allocation.)
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, PartialEq)]
pub enum BoardLine {
    /// `Waiting on MATLAB...`: the board has just reset.
    Banner,
    /// `Starting calibration.`
    Starting,
    /// A progress line: digits only (the board prints a digit per gauge as it trims it).
    Progress,
    /// `Leg<N> complete.`
    LegComplete(usize),
    /// `Gauge <G> on leg <L> is broken or unplugged. ...`: the board stops for good.
    Broken(Channel),
    /// `Gauge <G> on leg <L> will not calibrate. ...`
    WillNotCalibrate(Channel),
    /// `Final value: <v>`, after a will-not-calibrate message.
    FinalValue(f64),
    /// `Done.`
    Done,
    /// A sample line.
    Sample(Counts),
}

/// Reads line `line_no` (1-based, counted from when the port was opened) of `port`. The line has
/// its CR LF removed.
pub fn parse(line: &str, port: &str, line_no: u64) -> Result<BoardLine, LineError> {
    let err = |problem| LineError {
        port: port.to_owned(),
        line: line_no,
        problem,
    };
    let t = line.trim();
    if t == BANNER {
        return Ok(BoardLine::Banner);
    }
    if t == STARTING {
        return Ok(BoardLine::Starting);
    }
    if t == DONE {
        return Ok(BoardLine::Done);
    }
    if !t.is_empty() && t.bytes().all(|b| b.is_ascii_digit()) {
        return Ok(BoardLine::Progress);
    }
    if let Some(n) = t
        .strip_prefix("Leg")
        .and_then(|r| r.strip_suffix(" complete."))
    {
        return match n.parse::<usize>() {
            Ok(n) if n < 6 => Ok(BoardLine::LegComplete(n)),
            _ => Err(err(LineProblem::Unknown(shorten(t)))),
        };
    }
    if let Some(v) = t.strip_prefix("Final value:") {
        return v
            .trim()
            .parse::<f64>()
            .map(BoardLine::FinalValue)
            .map_err(|_| err(LineProblem::Unknown(shorten(t))));
    }
    if let Some(rest) = t.strip_prefix("Gauge ") {
        return gauge_message(rest).ok_or_else(|| err(LineProblem::Unknown(shorten(t))));
    }
    sample(t).map(BoardLine::Sample).map_err(err)
}

/// `<G> on leg <L> is broken ...` or `<G> on leg <L> will not calibrate ...`.
fn gauge_message(rest: &str) -> Option<BoardLine> {
    let (g, rest) = rest.split_once(" on leg ")?;
    let (l, rest) = rest.split_once(' ')?;
    let channel = Channel::on_board(l.parse().ok()?, g.parse().ok()?)?;
    if rest.starts_with("is broken or unplugged") {
        Some(BoardLine::Broken(channel))
    } else if rest.starts_with("will not calibrate") {
        Some(BoardLine::WillNotCalibrate(channel))
    } else {
        None
    }
}

/// A sample line: exactly 36 numbers, each 0..=1023.
fn sample(t: &str) -> Result<Counts, LineProblem> {
    let words: Vec<&str> = t.split_ascii_whitespace().collect();
    let mut counts = [0.0; CHANNELS];
    // Text that is not a list of numbers at all is garbage, not a wrong count of numbers.
    if words.is_empty() || words.iter().all(|w| w.parse::<f64>().is_err()) {
        return Err(LineProblem::Unknown(shorten(t)));
    }
    if words.len() != CHANNELS {
        return Err(LineProblem::Count(words.len()));
    }
    for (column, w) in words.iter().enumerate() {
        let channel = Channel::at_column(column).expect("36 columns");
        let v: f64 = w.parse().map_err(|_| LineProblem::NotANumber {
            channel,
            text: shorten(w),
        })?;
        if !(0.0..=MAX_COUNT).contains(&v) {
            return Err(LineProblem::OutOfRange { channel, value: v });
        }
        counts[column] = v;
    }
    Ok(counts)
}

/// At most 60 characters of a bad line, printable, for a message.
fn shorten(t: &str) -> String {
    let clean: String = t
        .chars()
        .map(|c| if c.is_control() { '?' } else { c })
        .collect();
    match clean.char_indices().nth(60) {
        Some((k, _)) => format!("{}...", &clean[..k]),
        None => clean,
    }
}

/// A sample as the board prints it: each count with two decimals and a trailing space.
pub fn format_sample(counts: &Counts) -> String {
    counts.iter().map(|v| format!("{v:.2} ")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::strain::channels::GaugeKind;
    use planner::model::Leg;

    fn line(n: usize, v: &str) -> String {
        vec![v; n].join(" ") + " "
    }

    #[test]
    fn the_boards_messages_read_as_the_protocol_says() {
        let p = |s| parse(s, "/dev/ttyACM1", 1).unwrap();
        assert_eq!(p("Waiting on MATLAB..."), BoardLine::Banner);
        assert_eq!(p("Starting calibration."), BoardLine::Starting);
        assert_eq!(p("012"), BoardLine::Progress);
        assert_eq!(p("Leg3 complete."), BoardLine::LegComplete(3));
        assert_eq!(p("Done."), BoardLine::Done);
        // Board leg 4 is LF (order LH, RH, LM, RM, LF, RF); gauge 0 is the trochanter axial.
        assert_eq!(
            p("Gauge 0 on leg 4 is broken or unplugged. Please check the cable."),
            BoardLine::Broken(Channel {
                leg: Leg::LF,
                kind: GaugeKind::TrochAxial
            })
        );
        assert_eq!(
            p("Gauge 5 on leg 1 will not calibrate. Please check the cable and board."),
            BoardLine::WillNotCalibrate(Channel {
                leg: Leg::RH,
                kind: GaugeKind::FemurAxial
            })
        );
        assert_eq!(p("Final value: 412"), BoardLine::FinalValue(412.0));
        let BoardLine::Sample(c) = p(&line(36, "300.00")) else {
            panic!()
        };
        assert_eq!(c, [300.0; 36]);
    }

    #[test]
    fn a_wrong_line_is_refused_naming_port_line_and_gauge() {
        let e = |s: &str| parse(s, "/dev/ttyACM1", 7).unwrap_err().to_string();
        assert_eq!(
            e(&line(35, "300.00")),
            "/dev/ttyACM1 line 7: 35 numbers where the strain board sends 36"
        );
        assert_eq!(
            e(&line(37, "300.00")),
            "/dev/ttyACM1 line 7: 37 numbers where the strain board sends 36"
        );
        let mut words = vec!["300.00"; 36];
        words[24] = "1024.00";
        assert_eq!(
            e(&words.join(" ")),
            "/dev/ttyACM1 line 7: column 25, LF_troch_axial (board leg 4, gauge 0): \
             1024 is outside the board's 0..1023 counts"
        );
        words[24] = "3x0";
        assert!(e(&words.join(" ")).contains("column 25, LF_troch_axial"));
        assert_eq!(
            e("\u{1}\u{0}hello"),
            "/dev/ttyACM1 line 7: not a line of the strain board: `??hello`"
        );
    }
}

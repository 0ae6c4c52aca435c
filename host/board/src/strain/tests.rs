//! The driver against the virtual board (in process, on a socket pair) and against scripted
//! boards that print the protocol's own words from `../shared/reference/lab-practice.md`.

use std::io::{ErrorKind, Read, Write};
use std::os::unix::net::UnixStream;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use super::channels::names;
use super::source::{Constant, Reading, StrainSource};
use super::*;

const PORT: &str = "/dev/ttyACM7";

pub(super) fn quick() -> Timeouts {
    Timeouts {
        banner: Duration::from_secs(5),
        calibration: Duration::from_secs(5),
        sample: Duration::from_secs(5),
    }
}

/// A virtual board with `faults`, unpaced, on a socket pair; the driver's end.
fn virtual_io(source: Box<dyn StrainSource>, faults: Vec<Fault>) -> UnixStream {
    board_on_a_socket(source, faults, false)
}

/// A virtual board with `faults` on a socket pair, paced like the real one when `paced`; the
/// driver's end.
pub(super) fn board_on_a_socket(
    source: Box<dyn StrainSource>,
    faults: Vec<Fault>,
    paced: bool,
) -> UnixStream {
    let (host, mut dev) = UnixStream::pair().unwrap();
    host.set_read_timeout(Some(Duration::from_millis(5)))
        .unwrap();
    dev.set_read_timeout(Some(Duration::from_millis(1)))
        .unwrap();
    std::thread::spawn(move || {
        let mut board = VirtualStrainBoard::new(source, faults, paced);
        let _ = board.serve(&mut dev, &AtomicBool::new(false));
    });
    host
}

fn virtual_board(faults: Vec<Fault>) -> StrainBoard<UnixStream> {
    StrainBoard::new(virtual_io(Box::new(Constant(0.0)), faults), PORT, quick())
}

fn gauge(name: &str) -> Channel {
    Channel::parse(name).unwrap()
}

/// A board that prints `text` in chunks of 7 bytes, then nothing (reads time out).
struct Script {
    text: Vec<u8>,
    at: usize,
}

fn script(lines: &[&str]) -> StrainBoard<Script> {
    let text = lines.iter().map(|l| format!("{l}\r\n")).collect::<String>();
    StrainBoard::new(
        Script {
            text: text.into_bytes(),
            at: 0,
        },
        PORT,
        Timeouts {
            banner: Duration::from_millis(300),
            calibration: Duration::from_millis(300),
            sample: Duration::from_millis(300),
        },
    )
}

impl Read for Script {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.at == self.text.len() {
            std::thread::sleep(Duration::from_millis(2));
            return Err(ErrorKind::TimedOut.into());
        }
        let n = 7.min(buf.len()).min(self.text.len() - self.at);
        buf[..n].copy_from_slice(&self.text[self.at..self.at + n]);
        self.at += n;
        Ok(n)
    }
}

impl Write for Script {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// The protocol's calibration of a board whose every gauge trims: banner, start, a digit per
/// gauge, `Leg<N> complete.` per leg, `Done.` (1 + 1 + 36 + 6 + 1 = 45 lines).
fn good_calibration() -> Vec<String> {
    let mut l = vec![
        "Waiting on MATLAB...".to_owned(),
        "Starting calibration.".to_owned(),
    ];
    for leg in 0..6 {
        for g in 0..6 {
            l.push(g.to_string());
        }
        l.push(format!("Leg{leg} complete."));
    }
    l.push("Done.".to_owned());
    l
}

#[test]
fn a_good_board_calibrates_and_streams_its_trimmed_counts() {
    let mut b = virtual_board(vec![]);
    let report = b.calibrate().unwrap();
    assert_eq!(report.not_calibrated, vec![]);
    let s = b.next_sample().unwrap();
    // lab-practice.md: each gauge is trimmed until it reads 300 +- 75 counts; no strain applied.
    assert!(
        s.counts.iter().all(|v| (225.0..=375.0).contains(v)),
        "{:?}",
        s.counts
    );
    // Line 46: the 45 lines of calibration come first.
    assert_eq!(s.line, 46);
    b.stop().unwrap();
}

#[test]
fn a_broken_gauge_stops_calibration_naming_gauge_and_leg() {
    let e = virtual_board(vec![Fault::Unplugged(gauge("LF_troch_axial"))])
        .calibrate()
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "/dev/ttyACM7: calibration stopped for good: gauge LF_troch_axial (board leg 4, gauge 0) \
         is broken or unplugged; check its cable and reset the board"
    );
    // The protocol's own words: gauge 2 on leg 0 is LH (legs LH, RH, ...), trochanter 45 deg.
    let mut lines = good_calibration()[..4].to_vec();
    lines.push("Gauge 2 on leg 0 is broken or unplugged. Please check the cable.".into());
    let l: Vec<&str> = lines.iter().map(String::as_str).collect();
    let e = script(&l).calibrate().unwrap_err().to_string();
    assert!(
        e.contains("gauge LH_troch_45 (board leg 0, gauge 2)"),
        "{e}"
    );
}

#[test]
fn a_gauge_that_will_not_calibrate_is_reported_with_its_final_value() {
    let report = virtual_board(vec![Fault::NoCalibrate(gauge("RM_femur_minus45"))])
        .calibrate()
        .unwrap();
    assert_eq!(
        report.not_calibrated,
        vec![NotCalibrated {
            channel: gauge("RM_femur_minus45"),
            final_value: Some(virtual_board::UNCALIBRATED),
        }]
    );
    // The protocol's words, inserted after gauge 5 of leg 1 (RH, femur axial).
    let mut lines = good_calibration();
    let at = lines.iter().position(|l| l == "Leg1 complete.").unwrap();
    lines.insert(
        at,
        "Gauge 5 on leg 1 will not calibrate. Please check the cable and board.".into(),
    );
    lines.insert(at + 1, "Final value: 412".into());
    let l: Vec<&str> = lines.iter().map(String::as_str).collect();
    let report = script(&l).calibrate().unwrap();
    assert_eq!(
        report.not_calibrated,
        vec![NotCalibrated {
            channel: gauge("RH_femur_axial"),
            final_value: Some(412.0),
        }]
    );
}

#[test]
fn a_board_that_never_says_done_times_out() {
    // The protocol's calibration without its last line, `Done.`.
    let mut lines = good_calibration();
    lines.pop();
    let l: Vec<&str> = lines.iter().map(String::as_str).collect();
    assert_eq!(
        script(&l).calibrate().unwrap_err().to_string(),
        "/dev/ttyACM7: the strain board did not say `Done.` within 0.3 s of calibrating \
         (6 of 6 legs complete)"
    );
    let mut b = StrainBoard::new(
        virtual_io(Box::new(Constant(0.0)), vec![Fault::NeverDone]),
        PORT,
        Timeouts {
            calibration: Duration::from_millis(500),
            ..quick()
        },
    );
    let e = b.calibrate().unwrap_err().to_string();
    assert!(
        e.starts_with("/dev/ttyACM7: the strain board did not say `Done.` within 0.5 s"),
        "{e}"
    );
}

#[test]
fn wrong_sample_lines_are_refused_with_port_and_line() {
    let n = |k: usize| vec!["300.00"; k].join(" ") + " ";
    for (bad, problem) in [
        (n(35), "35 numbers where the strain board sends 36"),
        (n(37), "37 numbers where the strain board sends 36"),
        (
            "#@!garbage".to_owned(),
            "not a line of the strain board: `#@!garbage`",
        ),
    ] {
        let mut lines = good_calibration();
        lines.push(n(36));
        lines.push(bad);
        let l: Vec<&str> = lines.iter().map(String::as_str).collect();
        let mut b = script(&l);
        b.calibrate().unwrap();
        assert_eq!(b.next_sample().unwrap().line, 46);
        // The bad line is line 47: 45 of calibration, one good sample.
        assert_eq!(
            b.next_sample().unwrap_err().to_string(),
            format!("/dev/ttyACM7 line 47: {problem}")
        );
    }
}

#[test]
fn a_reset_mid_stream_is_detected_and_named() {
    let mut b = virtual_board(vec![Fault::ResetAt(10)]);
    b.calibrate().unwrap();
    for _ in 0..10 {
        b.next_sample().unwrap();
    }
    // Lines 46..=55 were the samples; the banner comes again on line 56.
    assert_eq!(
        b.next_sample().unwrap_err().to_string(),
        "/dev/ttyACM7 line 56: the strain board reset (its banner came again) after 10 samples; \
         its calibration is lost"
    );
}

#[test]
fn a_servo_board_is_told_apart_by_its_silence_or_binary_frames() {
    // The servo board's link: COBS frames end in a zero byte; it never prints the banner.
    let mut b = StrainBoard::new(
        Script {
            text: vec![0x03, 0x11, 0x22, 0x00, 0x02, 0x05, 0x00],
            at: 0,
        },
        PORT,
        Timeouts {
            banner: Duration::from_millis(200),
            ..quick()
        },
    );
    let e = b.calibrate().unwrap_err().to_string();
    assert!(
        e.starts_with("/dev/ttyACM7: no `Waiting on MATLAB...` banner within 0.2 s:")
            && e.contains("the servo board's link"),
        "{e}"
    );
    assert!(port::check_not_servo_port("/dev/ttyACM0", "/dev/ttyACM0").is_err());
    assert!(port::check_not_servo_port("virtual", "virtual").is_ok());
}

/// Waits (at most a minute, however slow the machine) until `done`.
fn wait_for(done: impl Fn() -> bool) {
    let until = Instant::now() + Duration::from_secs(60);
    while !done() {
        assert!(Instant::now() < until, "gave up waiting");
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// Strain at one gauge far below what the ADC can show (counts saturate at 0).
struct OneSaturated;
impl StrainSource for OneSaturated {
    fn reading(&mut self, _k: u64, _t_s: f64) -> Reading {
        let mut s = [0.0; 36];
        s[Channel::parse("LM_troch_transverse").unwrap().column()] = -10_000.0;
        Reading::Microstrain(s)
    }
}

#[test]
fn the_recorder_keeps_what_it_read_when_the_board_goes_away() {
    let dir = tempfile::tempdir().unwrap();
    let epoch = Instant::now();
    let io = virtual_io(Box::new(OneSaturated), vec![Fault::HangUpAt(25)]);
    let rec = StrainRecorder::start_on(Box::new(io), PORT, dir.path(), epoch, quick());
    // The board hangs up by itself after 25 samples.
    wait_for(|| rec.ended());
    let e = rec.finish().unwrap_err();
    assert_eq!(e.samples, 25);
    let msg = e.to_string();
    assert!(
        msg.starts_with(
            "strain recording stopped: /dev/ttyACM7: the strain board went away (unplugged?) \
             after 25 samples; 25 samples kept in"
        ),
        "{msg}"
    );
    let text = std::fs::read_to_string(dir.path().join("strain.csv")).unwrap();
    let mut rows = csv::Reader::from_reader(text.as_bytes());
    let header: Vec<String> = rows.headers().unwrap().iter().map(str::to_owned).collect();
    assert_eq!(header[0], "time_s");
    assert_eq!(header[1..], names()[..]);
    let rows: Vec<csv::StringRecord> = rows.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), 25);
    let col = 1 + Channel::parse("LM_troch_transverse").unwrap().column();
    let mut last = f64::NEG_INFINITY;
    for r in &rows {
        let t: f64 = r[0].parse().unwrap();
        assert!(
            t >= 0.0 && t >= last,
            "host time runs forward from the epoch"
        );
        last = t;
        // 300 + 0.5 x -10000 = -4700: saturated at 0; the others read their baseline.
        assert_eq!(&r[col], "0");
        assert_eq!(&r[1], "300");
    }
    let base = std::fs::read_to_string(dir.path().join("strain_baseline.csv")).unwrap();
    assert!(
        base.lines()
            .nth(1)
            .unwrap()
            .starts_with("first_sample,300,")
    );
}

#[test]
fn a_channel_at_a_rail_for_the_whole_recording_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let io = virtual_io(Box::new(OneSaturated), vec![]);
    let rec = StrainRecorder::start_on(Box::new(io), PORT, dir.path(), Instant::now(), quick());
    wait_for(|| rec.samples() >= 5);
    let done = rec.finish().unwrap();
    assert!(done.samples > 0);
    let stuck: Vec<String> = done.stuck.iter().map(ToString::to_string).collect();
    assert_eq!(
        stuck,
        ["LM_troch_transverse (board leg 2, gauge 1) stuck at 0 counts"]
    );
}

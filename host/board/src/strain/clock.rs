//! The map from the host's clock (the strain board's samples are stamped with it) to the servo
//! board's clock (telemetry carries it), fitted from the arrival of every telemetry record.
//!
//! Each telemetry record says its board time `b` and arrives at host time `h = a + r b + L`,
//! where `L >= 0` is its delivery latency (the board's USB frame, the host's scheduling). A least
//! squares line gives the rate `r` (host seconds per board second: 1 within the crystals'
//! tolerance on hardware, the simulation's pace on a simulated robot); the offset `a` is then the
//! *smallest* residual, the record that came fastest, so a mapped time is late by only the least
//! latency seen instead of the mean one. The spread of the other residuals above it (their 95th
//! percentile) is the delivery jitter the fit has rejected: reported, not hidden.

/// Telemetry arrivals, host seconds against board seconds.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ClockMap {
    points: Vec<(f64, f64)>,
}

/// The fitted map `host = offset + rate x board`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClockFit {
    /// Host seconds per board second.
    pub rate: f64,
    /// Host time of board time 0, s (the fastest record's: latency at its least).
    pub offset_s: f64,
    /// Records the fit used.
    pub records: usize,
    /// 95th percentile of the records' lateness beyond the fastest one, s (their delivery jitter).
    pub jitter_p95_s: f64,
}

impl ClockMap {
    /// A record of board time `board_s` arrived at host time `host_s`.
    pub fn note(&mut self, host_s: f64, board_s: f64) {
        if host_s.is_finite() && board_s.is_finite() {
            self.points.push((host_s, board_s));
        }
    }

    /// The map, or None before the first record.
    pub fn fit(&self) -> Option<ClockFit> {
        let n = self.points.len();
        if n == 0 {
            return None;
        }
        let nf = n as f64;
        let (mh, mb) = self
            .points
            .iter()
            .fold((0.0, 0.0), |(h, b), p| (h + p.0 / nf, b + p.1 / nf));
        let (sbb, sbh) = self.points.iter().fold((0.0, 0.0), |(bb, bh), p| {
            (bb + (p.1 - mb) * (p.1 - mb), bh + (p.1 - mb) * (p.0 - mh))
        });
        // Less than a millisecond of board time says nothing about a rate: take the clocks as equal.
        let span = self.points.iter().map(|p| p.1).fold(f64::MIN, f64::max)
            - self.points.iter().map(|p| p.1).fold(f64::MAX, f64::min);
        let rate = if span > 1e-3 && sbb > 0.0 {
            sbh / sbb
        } else {
            1.0
        };
        let mut residuals: Vec<f64> = self.points.iter().map(|p| p.0 - rate * p.1).collect();
        residuals.sort_by(f64::total_cmp);
        let offset_s = residuals[0];
        let p95 = residuals[((n - 1) as f64 * 0.95).round() as usize] - offset_s;
        Some(ClockFit {
            rate,
            offset_s,
            records: n,
            jitter_p95_s: p95,
        })
    }
}

impl ClockFit {
    /// Board time of host time `host_s`.
    pub fn board_s(&self, host_s: f64) -> f64 {
        (host_s - self.offset_s) / self.rate
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A board clock 100 ppm fast of the host's, 7 s after the host's zero, with latencies of
    /// 1 ms (every tenth record: the fastest) to 4 ms: the fit finds the rate and the offset
    /// plus the least latency, by hand 7.001 s, and a jitter of at most 3 ms.
    #[test]
    fn the_fit_takes_the_fastest_record_as_the_offset() {
        let mut m = ClockMap::default();
        for i in 0..200 {
            let b = f64::from(i) * 0.01;
            let latency = if i % 10 == 0 {
                0.001
            } else {
                0.001 + 0.003 * f64::from((i * 7919) % 97) / 96.0
            };
            m.note(7.0 + 1.0001 * b + latency, b);
        }
        let f = m.fit().unwrap();
        assert!((f.rate - 1.0001).abs() < 2e-4, "{}", f.rate);
        // The rate's error over 2 s of board time moves the envelope by well under 1 ms.
        assert!((f.offset_s - 7.001).abs() < 5e-4, "{}", f.offset_s);
        assert!(
            f.jitter_p95_s > 0.001 && f.jitter_p95_s <= 0.0035,
            "{}",
            f.jitter_p95_s
        );
        assert_eq!(f.records, 200);
        // Board time of a host instant: the inverse of the line.
        assert!((f.board_s(f.offset_s + f.rate * 1.5) - 1.5).abs() < 1e-12);
    }

    /// A simulated robot running at three times real time: the rate is a third.
    #[test]
    fn a_simulation_faster_than_real_time_has_its_pace_as_the_rate() {
        let mut m = ClockMap::default();
        for i in 0..50 {
            let b = f64::from(i) * 0.03;
            m.note(0.2 + b / 3.0, b);
        }
        let f = m.fit().unwrap();
        assert!((f.rate - 1.0 / 3.0).abs() < 1e-12);
        assert!((f.offset_s - 0.2).abs() < 1e-12);
        assert!(f.jitter_p95_s.abs() < 1e-12);
    }

    #[test]
    fn one_record_gives_equal_clocks_and_none_gives_no_map() {
        assert_eq!(ClockMap::default().fit(), None);
        let mut m = ClockMap::default();
        m.note(3.0, 0.0);
        let f = m.fit().unwrap();
        assert_eq!((f.rate, f.offset_s, f.records), (1.0, 3.0, 1));
    }
}

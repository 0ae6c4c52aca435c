//! Per-gauge summaries of a stream: running means, and channels stuck at a rail (every sample 0,
//! or every sample 1023: an unplugged or shorted gauge after calibration).

use super::channels::{CHANNELS, Channel};
use super::line::{Counts, MAX_COUNT};

/// A channel that never left a rail.
#[derive(Debug, Clone, PartialEq)]
pub struct Stuck {
    pub channel: Channel,
    /// 0 or 1023.
    pub at: f64,
}

impl std::fmt::Display for Stuck {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} stuck at {} counts", self.channel.describe(), self.at)
    }
}

/// Running per-channel mean and rail check.
#[derive(Debug, Clone, PartialEq)]
pub struct GaugeStats {
    n: u64,
    sum: [f64; CHANNELS],
    all_zero: [bool; CHANNELS],
    all_full: [bool; CHANNELS],
}

impl Default for GaugeStats {
    fn default() -> Self {
        Self {
            n: 0,
            sum: [0.0; CHANNELS],
            all_zero: [true; CHANNELS],
            all_full: [true; CHANNELS],
        }
    }
}

impl GaugeStats {
    pub fn add(&mut self, counts: &Counts) {
        self.n += 1;
        for (c, &v) in counts.iter().enumerate() {
            self.sum[c] += v;
            self.all_zero[c] &= v == 0.0;
            self.all_full[c] &= v == MAX_COUNT;
        }
    }

    pub fn samples(&self) -> u64 {
        self.n
    }

    /// Mean counts per channel (None before the first sample).
    pub fn means(&self) -> Option<Counts> {
        (self.n > 0).then(|| self.sum.map(|s| s / self.n as f64))
    }

    /// Channels whose every sample was 0 or every sample 1023 (none before the first sample).
    pub fn stuck(&self) -> Vec<Stuck> {
        if self.n == 0 {
            return Vec::new();
        }
        (0..CHANNELS)
            .filter_map(|c| {
                let at = if self.all_zero[c] {
                    0.0
                } else if self.all_full[c] {
                    MAX_COUNT
                } else {
                    return None;
                };
                Some(Stuck {
                    channel: Channel::at_column(c).expect("36 columns"),
                    at,
                })
            })
            .collect()
    }
}

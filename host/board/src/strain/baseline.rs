//! The zero-strain baseline as the lab takes it (the mean of 20 samples with the robot held
//! unloaded before the trial, or the first sample of the trial) and microstrain from counts where
//! a gain is known. No gain is known by default: the lab has not published its amplifier gains,
//! so strain files carry raw counts and the baseline, and microstrain only for gauges given a gain.

use super::channels::CHANNELS;
use super::line::Counts;

/// Samples the lab averages with the robot held unloaded.
pub const UNLOADED_SAMPLES: usize = 20;

/// How a baseline was taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BaselineMethod {
    /// The mean of [`UNLOADED_SAMPLES`] samples, robot held unloaded.
    MeanOfUnloaded,
    /// The first sample of the trial.
    FirstSample,
}

impl BaselineMethod {
    /// The method's name in a baseline file.
    pub fn name(self) -> &'static str {
        match self {
            BaselineMethod::MeanOfUnloaded => "mean_of_20_unloaded",
            BaselineMethod::FirstSample => "first_sample",
        }
    }
}

/// Zero-strain counts per channel.
#[derive(Debug, Clone, PartialEq)]
pub struct Baseline {
    pub method: BaselineMethod,
    pub counts: Counts,
}

impl Baseline {
    /// The mean of the first [`UNLOADED_SAMPLES`] of `samples` (None if there are fewer).
    pub fn mean_of_unloaded(samples: &[Counts]) -> Option<Baseline> {
        let first = samples.get(..UNLOADED_SAMPLES)?;
        let mut counts = [0.0; CHANNELS];
        for s in first {
            for (m, v) in counts.iter_mut().zip(s) {
                *m += v / UNLOADED_SAMPLES as f64;
            }
        }
        Some(Baseline {
            method: BaselineMethod::MeanOfUnloaded,
            counts,
        })
    }

    /// The first sample.
    pub fn first_sample(sample: &Counts) -> Baseline {
        Baseline {
            method: BaselineMethod::FirstSample,
            counts: *sample,
        }
    }
}

/// Counts per microstrain for each channel, where known (none by default).
#[derive(Debug, Clone, PartialEq)]
pub struct Gains(pub [Option<f64>; CHANNELS]);

impl Default for Gains {
    fn default() -> Self {
        Self([None; CHANNELS])
    }
}

impl Gains {
    /// Microstrain of each channel: (counts - baseline) / gain, None where no gain is known.
    pub fn microstrain(&self, counts: &Counts, baseline: &Baseline) -> [Option<f64>; CHANNELS] {
        let mut out = [None; CHANNELS];
        for (c, o) in out.iter_mut().enumerate() {
            *o = self.0[c].map(|g| (counts[c] - baseline.counts[c]) / g);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_unloaded_baseline_is_the_mean_of_the_first_twenty() {
        // Samples 1..=25 on every channel: the first twenty average (1 + 20) / 2 = 10.5.
        let samples: Vec<Counts> = (1..=25).map(|k| [k as f64; CHANNELS]).collect();
        let b = Baseline::mean_of_unloaded(&samples).unwrap();
        assert!(b.counts.iter().all(|&v| (v - 10.5).abs() < 1e-12));
        assert_eq!(Baseline::mean_of_unloaded(&samples[..19]), None);
        assert_eq!(Baseline::first_sample(&samples[3]).counts, [4.0; CHANNELS]);
    }

    #[test]
    fn microstrain_only_where_a_gain_is_known() {
        let base = Baseline::first_sample(&[300.0; CHANNELS]);
        let mut g = Gains::default();
        g.0[2] = Some(0.5);
        let e = g.microstrain(&[350.0; CHANNELS], &base);
        // (350 - 300) counts / 0.5 counts per microstrain = 100 microstrain.
        assert_eq!(e[2], Some(100.0));
        assert_eq!(e[0], None);
    }
}

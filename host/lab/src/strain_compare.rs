//! A recording's strain against the plan's prediction, gauge by gauge (issue 26 item 7): each
//! strain sample of a trial (`strain.csv`, aligned on the telemetry's clock by `record
//! --strain`) is given the slice of the step the robot was playing then (the telemetry record
//! nearest in time), and paired with the plan's predicted microstrain at that slice (the plan
//! directory's `strain.csv`).
//!
//! Per gauge: the R^2 over the step phase ([`regression_r2`]: blind to scale and offset, since
//! the gain is what is unknown) of counts above the zero-strain baseline against predicted
//! microstrain, and the gain, counts per predicted microstrain, fitted through the origin (the
//! baseline is the zero: `sum(x y) / sum(x^2)`), which a lab can save (`strain_gains.csv`); and
//! the RMS of the recorded microstrain against the prediction, the counts read through the plan
//! model's calibration file where it names the gauge (calibrated), else through the virtual
//! board's invented gain (ESTIMATE). The calibration itself is fitted from a standing trial
//! (`crate::calibrate`).

use std::collections::BTreeMap;
use std::path::Path;

use board::strain::beside::read_aligned;
use board::strain::channels::{self, CHANNELS};
use planner::analysis::fit::{regression_r2, rms};

use board::strain::virtual_board::DEFAULT_GAIN;

use crate::bail;
use crate::error::{Context, Result};
use crate::replay::Reading;

/// The calibration file's name.
pub const GAINS_CSV: &str = "strain_gains.csv";

/// One gauge's comparison.
#[derive(Debug, Clone, PartialEq)]
pub struct GaugeFit {
    pub gauge: String,
    /// Strain samples paired with a predicted value.
    pub samples: usize,
    /// R^2 of counts above baseline against predicted microstrain (None: either is flat).
    pub r2: Option<f64>,
    /// Counts per predicted microstrain, through the origin (None: the prediction is zero).
    pub gain: Option<f64>,
    /// RMS of counts above baseline less gain x prediction, counts.
    pub rms_residual_counts: Option<f64>,
    /// How the counts were read as microstrain: the gain of the plan model's calibration file
    /// (calibrated) or the virtual board's invented default (ESTIMATE).
    pub reading: Reading,
    /// That reading's counts per microstrain.
    pub reading_gain: f64,
    /// RMS of the recorded microstrain (counts above baseline / `reading_gain`) less the
    /// prediction.
    pub rms_microstrain: Option<f64>,
}

/// Fits every gauge from `pairs[gauge]` = (predicted microstrain, counts above baseline).
pub fn fit_gauges(names: &[String], pairs: &[Vec<(f64, f64)>]) -> Vec<GaugeFit> {
    names
        .iter()
        .zip(pairs)
        .map(|(gauge, p)| {
            let (x, y): (Vec<f64>, Vec<f64>) = p.iter().copied().unzip();
            let sxx: f64 = x.iter().map(|v| v * v).sum();
            let sxy: f64 = p.iter().map(|(a, b)| a * b).sum();
            let gain = (sxx > 0.0).then(|| sxy / sxx);
            GaugeFit {
                gauge: gauge.clone(),
                samples: p.len(),
                r2: regression_r2(&x, &y),
                gain,
                rms_residual_counts: gain.and_then(|g| rms(p.iter().map(|(a, b)| b - g * a))),
                reading: Reading::Estimate,
                reading_gain: DEFAULT_GAIN,
                rms_microstrain: rms(p.iter().map(|(a, b)| b / DEFAULT_GAIN - a)),
            }
        })
        .collect()
}

/// Predicted microstrain by gauge name and slice from a plan directory's `strain.csv`.
fn predicted(plan_dir: &Path) -> Result<BTreeMap<String, Vec<f64>>> {
    let path = plan_dir.join(planner::strain::csv::STRAIN_CSV);
    let text = std::fs::read_to_string(&path)
        .with_context(|| format!("reading {} (written by `dbot plan`)", path.display()))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let col = |n: &str| header.iter().position(|h| *h == n);
    let (Some(s), Some(g), Some(m)) = (col("slice"), col("gauge"), col("microstrain")) else {
        bail!(
            "{}: no slice, gauge and microstrain columns",
            path.display()
        );
    };
    let mut out: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    for (i, l) in lines.enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let c: Vec<&str> = l.split(',').collect();
        let (Some(slice), Some(value)) = (
            c.get(s).and_then(|v| v.parse::<usize>().ok()),
            c.get(m).and_then(|v| v.parse::<f64>().ok()),
        ) else {
            bail!(
                "{} line {}: no slice number or microstrain",
                path.display(),
                i + 2
            );
        };
        let v = out.entry(c.get(g).unwrap_or(&"").to_string()).or_default();
        if v.len() <= slice {
            v.resize(slice + 1, f64::NAN);
        }
        v[slice] = value;
    }
    Ok(out)
}

/// The zero-strain counts of a trial (`strain_baseline.csv`), in column order.
fn baseline(trial: &Path) -> Result<[f64; CHANNELS]> {
    let path = trial.join(board::strain::recorder::BASELINE_CSV);
    let text = std::fs::read_to_string(&path).with_context(|| {
        format!(
            "reading {} (written by `dbot record --strain`)",
            path.display()
        )
    })?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let row: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let mut out = [0.0; CHANNELS];
    for (c, name) in channels::names().iter().enumerate() {
        let v = header
            .iter()
            .position(|h| h == name)
            .and_then(|i| row.get(i))
            .and_then(|v| v.parse::<f64>().ok());
        let Some(v) = v else {
            bail!("{}: no baseline count for {name}", path.display());
        };
        out[c] = v;
    }
    Ok(out)
}

/// Compares the strain of the trial folder `trial` with the prediction of `plan_dir`: one fit per
/// gauge the plan predicts, in the board's column order, each read through the plan model's
/// calibration (`model.toml` naming one) where it has the gauge.
pub fn compare_trial(trial: &Path, plan_dir: &Path) -> Result<Vec<GaugeFit>> {
    let tr = board::trial::read_trial(trial)
        .map_err(|e| crate::LabError::invalid(format!("{}: {e}", trial.display())))?;
    let strain = read_aligned(&trial.join(board::strain::recorder::STRAIN_CSV))
        .map_err(|e| crate::LabError::invalid(e.to_string()))?;
    let zero = baseline(trial)?;
    let pred = predicted(plan_dir)?;
    // One (time, slice) per bus cycle, in time order; only while walking (steps known: before the
    // last one ended).
    let walking = |step: u32| tr.meta.steps.is_none_or(|n| step < n);
    let mut records: Vec<(f64, usize)> = Vec::new();
    for r in tr.rows.iter().filter(|r| r.joint == 0 && walking(r.step)) {
        records.push((r.time_s, usize::from(r.slice)));
    }
    if records.is_empty() {
        bail!("{}: no telemetry of a walking step", trial.display());
    }
    let names = channels::names();
    let mut pairs = vec![Vec::new(); CHANNELS];
    for (t, counts) in strain.time_s.iter().zip(&strain.counts) {
        let Some(t) = *t else { continue };
        // Samples outside the walk's records (before its start, after its end) have no slice.
        let (first, last) = (records[0].0, records[records.len() - 1].0);
        if t < first || t > last {
            continue;
        }
        let i = records.partition_point(|r| r.0 < t);
        let near = match (records.get(i.wrapping_sub(1)), records.get(i)) {
            (Some(a), Some(b)) if t - a.0 <= b.0 - t => a,
            (_, Some(b)) => b,
            (Some(a), None) => a,
            (None, None) => continue,
        };
        for (c, name) in names.iter().enumerate() {
            if let Some(&x) = pred.get(name).and_then(|v| v.get(near.1))
                && x.is_finite()
            {
                pairs[c].push((x, counts[c] - zero[c]));
            }
        }
    }
    let (names, pairs): (Vec<String>, Vec<Vec<(f64, f64)>>) = names
        .into_iter()
        .zip(pairs)
        .filter(|(n, _)| pred.contains_key(n))
        .unzip();
    if names.is_empty() {
        bail!(
            "{}: the plan predicts none of the strain board's gauges",
            plan_dir.display()
        );
    }
    let mut fits = fit_gauges(&names, &pairs);
    let model_toml = plan_dir.join(planner::plan_dir::columns::MODEL_TOML);
    if model_toml.exists() {
        let model = planner::model::load(&model_toml)?;
        for (f, p) in fits.iter_mut().zip(&pairs) {
            (f.reading, f.reading_gain) = Reading::of_gauge(&model, &f.gauge);
            f.rms_microstrain = rms(p.iter().map(|(a, b)| b / f.reading_gain - a));
        }
    }
    Ok(fits)
}

/// The fits as a markdown table, each gauge saying how its counts were read.
pub fn table(fits: &[GaugeFit]) -> String {
    let num = |v: Option<f64>| v.map_or("-".into(), |v| format!("{:.4}", v + 0.0));
    crate::markdown::table(
        &[
            "gauge",
            "samples",
            "R^2",
            "counts per microstrain",
            "RMS residual (counts)",
            "RMS microstrain",
            "reading",
        ],
        fits.iter().map(|f| {
            vec![
                f.gauge.clone(),
                f.samples.to_string(),
                f.r2.map_or("-".into(), |v| format!("{v:.3}")),
                num(f.gain),
                num(f.rms_residual_counts),
                num(f.rms_microstrain),
                format!(
                    "{} ({:.4} counts per microstrain)",
                    f.reading.word(),
                    f.reading_gain
                ),
            ]
        }),
    )
}

/// `gauge,counts_per_microstrain,r2,samples`: the fitted gains as a calibration file (empty cells
/// where there is no value).
pub fn gains_csv(fits: &[GaugeFit]) -> String {
    // `+ 0.0` writes a gain of -0 (a zero sum of negative products) as 0.
    let cell = |v: Option<f64>| v.map_or(String::new(), |v| format!("{:.6}", v + 0.0));
    let mut s = String::from("gauge,counts_per_microstrain,r2,samples\n");
    for f in fits {
        s.push_str(&format!(
            "{},{},{},{}\n",
            f.gauge,
            cell(f.gain),
            cell(f.r2),
            f.samples
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Counts = 0.5 x prediction exactly: gain 0.5, R^2 1, no residual. Counts = -2 x prediction
    /// plus an alternating noise of 1 count: gain near -2. A flat prediction has no gain and no
    /// R^2.
    #[test]
    fn gains_and_r2_against_hand_built_pairs() {
        let x: Vec<f64> = (0..20)
            .map(|i| 100.0 * (f64::from(i) * 0.3).sin())
            .collect();
        let exact: Vec<(f64, f64)> = x.iter().map(|&v| (v, 0.5 * v)).collect();
        let noisy: Vec<(f64, f64)> = x
            .iter()
            .enumerate()
            .map(|(i, &v)| (v, -2.0 * v + if i % 2 == 0 { 1.0 } else { -1.0 }))
            .collect();
        let flat: Vec<(f64, f64)> = (0..20).map(|_| (0.0, 3.0)).collect();
        let names = ["a", "b", "c"].map(String::from);
        let f = fit_gauges(&names, &[exact, noisy, flat]);
        assert!((f[0].gain.unwrap() - 0.5).abs() < 1e-12);
        assert!((f[0].r2.unwrap() - 1.0).abs() < 1e-12);
        assert!(f[0].rms_residual_counts.unwrap() < 1e-9);
        // sum(x e) / sum(x^2) with |e| = 1 and |x| up to 100: the gain moves by under 1 %.
        assert!((f[1].gain.unwrap() + 2.0).abs() < 0.02, "{:?}", f[1].gain);
        assert!(f[1].r2.unwrap() > 0.999);
        assert_eq!((f[2].gain, f[2].r2), (None, None));
        let csv = gains_csv(&f);
        assert!(
            csv.starts_with("gauge,counts_per_microstrain,r2,samples\na,0.500000,1.000000,20\n")
        );
        assert!(csv.ends_with("c,,,20\n"));
    }
}

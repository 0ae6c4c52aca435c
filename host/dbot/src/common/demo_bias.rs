//! What the torque bias buys: the posture error of a walk, with and without it, over the same
//! whole steps the fits use (after the first). The joint angle error is the present angle minus the
//! plan's angle at that moment: with the bias on the recorder's `planned_rad` (the goal minus the
//! bias), with it off the goal itself (the firmware then commands the planned angle). The thorax
//! height error is the plan's height (the stance it was set down in) minus the simulated height.

use board::record::Row;
use physics::WalkLog;

/// Posture error of one walk.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Posture {
    /// RMS over joints and cycles of present - planned angle, rad.
    pub rms_rad: f64,
    /// Mean and largest thorax sag below the planned height while walking, m (negative: above).
    pub sag_mean_m: f64,
    pub sag_max_m: f64,
}

/// The posture error of a walk of `steps` steps from its telemetry rows and log; `bias_on` says
/// whether the firmware added the torque bias to the goals.
pub fn posture(
    rows: &[Row],
    log: &WalkLog,
    planned_height_m: f64,
    steps: u32,
    bias_on: bool,
) -> Posture {
    let counted = |step: u32| step >= 1 && step < steps;
    let (mut n, mut sq) = (0usize, 0.0);
    for r in rows.iter().filter(|r| counted(r.step)) {
        let reference = if bias_on {
            r.planned_rad.unwrap_or(r.commanded_rad)
        } else {
            r.commanded_rad
        };
        n += 1;
        sq += (r.present_rad - reference).powi(2);
    }
    let sags: Vec<f64> = log
        .samples
        .iter()
        .filter(|s| s.walking && s.playback.is_some_and(|(step, _)| counted(step)))
        .map(|s| planned_height_m - s.thorax.0[2])
        .collect();
    Posture {
        rms_rad: if n > 0 { (sq / n as f64).sqrt() } else { 0.0 },
        sag_mean_m: if sags.is_empty() {
            0.0
        } else {
            sags.iter().sum::<f64>() / sags.len() as f64
        },
        sag_max_m: sags.iter().copied().reduce(f64::max).unwrap_or(0.0),
    }
}

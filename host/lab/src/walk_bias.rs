//! What the torque bias buys: the posture error of a walk, with and without it, over the same
//! whole steps the fits use (after the first). The joint angle error is the present angle minus the
//! plan's angle at that moment: with the bias on the recorder's `planned_rad` (the goal minus the
//! bias), with it off the goal itself (the firmware then commands the planned angle). The thorax
//! height error is the plan's height (the stance it was set down in) minus the simulated height.

use board::record::Row;
use physics::WalkLog;
use planner::analysis::fit::rms;

use crate::walk_files::Walk;
use crate::walk_fits::counted;

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
    let errors = rows.iter().filter(|r| counted(r.step, steps)).map(|r| {
        let reference = if bias_on {
            r.planned_rad.unwrap_or(r.commanded_rad)
        } else {
            r.commanded_rad
        };
        r.present_rad - reference
    });
    let rms_rad = rms(errors).unwrap_or(0.0);
    let sags: Vec<f64> = log
        .samples
        .iter()
        .filter(|s| s.walking && s.playback.is_some_and(|(step, _)| counted(step, steps)))
        .map(|s| planned_height_m - s.thorax.0[2])
        .collect();
    Posture {
        rms_rad,
        sag_mean_m: if sags.is_empty() {
            0.0
        } else {
            sags.iter().sum::<f64>() / sags.len() as f64
        },
        sag_max_m: sags.iter().copied().reduce(f64::max).unwrap_or(0.0),
    }
}

/// The posture error of the forward walk with the bias and of the one without it, among `walks`
/// (`None` unless both were walked with a body).
pub fn bias_gain(walks: &[Walk], planned_height_m: f64, steps: u32) -> Option<(Posture, Posture)> {
    let find = |bias_on: bool| {
        walks
            .iter()
            .find(|w| w.bias_on == bias_on && w.direction == protocol::Direction::Forward)
    };
    let (on, off) = (find(true)?, find(false)?);
    let (log_on, log_off) = (on.log.as_ref()?, off.log.as_ref()?);
    Some((
        posture(on.rec.rows(), log_on, planned_height_m, steps, true),
        posture(off.rec.rows(), log_off, planned_height_m, steps, false),
    ))
}

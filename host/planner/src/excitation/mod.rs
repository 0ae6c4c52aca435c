//! Excitation trials: gaits a lab plays on the robot to identify its servos and body (issue #37),
//! each a step table played and recorded as an ordinary trial.
//!
//! - [`ExcitationKind::Suspended`]: the robot hangs with its feet in the air. One table per joint
//!   kind (ThC1, ThC3, CTr, TrF, FTi on Drosophibot II), moving that joint on every leg at once
//!   while the leg's other joints hold the resting posture: steps (up, back, down, back, each
//!   followed by a hold) and a linear chirp, within the joint's limits and under a fraction of
//!   its servo's no-load speed ([`suspended`]).
//! - [`ExcitationKind::Standing`]: the robot stands on its feet and shifts its thorax slowly
//!   (heave, surge, sway, roll, pitch, yaw), the feet held where they rest by the inverse
//!   kinematics: the joints change posture under the body's weight ([`standing`]).
//!
//! Every table starts and ends at the resting posture (a table loops) and carries no torque bias
//! (torques 0): the goals are what the servos are asked to hold. The board's rules (slot size,
//! servo feasibility, the P gain's stiffness) judge the tables as any gait's
//! (`board::rules::build::excitation_table`).

mod signal;
mod standing;
mod suspended;

pub use signal::{Chirp, Ramp};
pub use standing::standing;
pub use suspended::suspended;

use serde::Serialize;

use crate::kinematics::KinematicsError;
use crate::model::{Leg, Model};

/// Which excitation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ExcitationKind {
    /// Feet in the air: per-joint steps and chirps.
    Suspended,
    /// Standing on the feet: slow posture changes under load.
    Standing,
}

impl ExcitationKind {
    pub const ALL: [ExcitationKind; 2] = [ExcitationKind::Suspended, ExcitationKind::Standing];

    /// The name `dbot excite --kind` and Python take.
    pub fn name(self) -> &'static str {
        match self {
            ExcitationKind::Suspended => "suspended",
            ExcitationKind::Standing => "standing",
        }
    }
}

impl std::fmt::Display for ExcitationKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for ExcitationKind {
    type Err = ExcitationError;

    fn from_str(s: &str) -> Result<Self, ExcitationError> {
        Self::ALL
            .into_iter()
            .find(|k| k.name() == s)
            .ok_or_else(|| ExcitationError::Kind(s.to_owned()))
    }
}

/// Why an excitation could not be made.
#[derive(Debug, thiserror::Error)]
pub enum ExcitationError {
    #[error("unknown excitation kind `{0}`: suspended or standing")]
    Kind(String),
    #[error(
        "joint {joint}: its range [{lo:.3}, {hi:.3}] rad is too small to excite (needs more than twice the {margin} rad margin)"
    )]
    Range {
        joint: String,
        lo: f64,
        hi: f64,
        margin: f64,
    },
    #[error("excitation `{trial}`: {source}")]
    Kinematics {
        trial: String,
        #[source]
        source: KinematicsError,
    },
    #[error("the model {model} has no servo-driven joint to excite")]
    NoJoints { model: String },
}

/// Settings of an excitation; [`Default`] is what `dbot excite` plays.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ExcitationOptions {
    /// Slice length of a suspended table, s (the board interpolates between slices).
    pub suspended_dt_s: f64,
    /// Slice length of a standing table, s.
    pub standing_dt_s: f64,
    /// Fraction of each joint's no-load speed the fastest move may reach (steps and chirps).
    pub speed_fraction: f64,
    /// Step size, rad (less where the joint's range is smaller).
    pub step_rad: f64,
    /// Hold after each step and around the chirp, s.
    pub hold_s: f64,
    /// Largest chirp amplitude, rad (less where the speed or the range allows less).
    pub chirp_amplitude_rad: f64,
    /// The chirp's frequency sweep, Hz, and its length, s (rounded to whole cycles).
    pub chirp_f0_hz: f64,
    pub chirp_f1_hz: f64,
    pub chirp_s: f64,
    /// Raised-cosine taper at each end of the chirp, s.
    pub chirp_taper_s: f64,
    /// Goals keep this far inside the joint limits, rad.
    pub limit_margin_rad: f64,
    /// Speed of the moves between the resting posture and an excitation's centre, rad/s.
    pub transfer_speed: f64,
    /// Standing: the thorax's excursions (m, rad) and the time each takes, s.
    pub heave_m: f64,
    pub shift_m: f64,
    pub tilt_rad: f64,
    pub posture_s: f64,
}

impl Default for ExcitationOptions {
    /// ESTIMATES chosen for Drosophibot II: a chirp over 0.1 to 2 Hz (the band identification in
    /// stages uses, ../shared/reference/sysid.md), steps and chirps at most half the no-load
    /// speed, 3 degrees from every limit, slow posture changes of 8 s.
    fn default() -> Self {
        Self {
            suspended_dt_s: 0.02,
            standing_dt_s: 0.04,
            speed_fraction: 0.5,
            step_rad: 0.15,
            hold_s: 1.0,
            chirp_amplitude_rad: 0.2,
            chirp_f0_hz: 0.1,
            chirp_f1_hz: 2.0,
            chirp_s: 20.0,
            chirp_taper_s: 0.5,
            limit_margin_rad: 3f64.to_radians(),
            transfer_speed: 0.5,
            heave_m: 0.01,
            shift_m: 0.015,
            tilt_rad: 4f64.to_radians(),
            posture_s: 8.0,
        }
    }
}

/// What one joint does over a span of an excitation table.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "motion", rename_all = "lowercase")]
pub enum Motion {
    /// A move at `speed` rad/s (the steps; the transfers from and to the resting posture).
    Ramp { from: f64, to: f64, speed: f64 },
    /// A linear chirp (see [`Chirp`]).
    Chirp {
        centre: f64,
        amplitude_rad: f64,
        f0_hz: f64,
        f1_hz: f64,
        taper_s: f64,
    },
    /// A posture change of the standing robot: the thorax's displacement named by `what`.
    Posture { what: &'static str, amplitude: f64 },
}

/// One span of an excitation table: which joint (or every joint, for a posture change), what it
/// does and when (s from the table's start).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Segment {
    /// The joint's name, or `"all"` for a posture change.
    pub joint: String,
    pub start_s: f64,
    pub end_s: f64,
    #[serde(flatten)]
    pub motion: Motion,
}

/// One excitation table: the goal of every model joint per slice, its stance bits and what it
/// does when.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ExcitationTrial {
    /// The table's name (at most 16 bytes: `sus-CTr`, `stand`).
    pub name: String,
    pub kind: ExcitationKind,
    /// Slice length, s; the table's period is `dt_s` times the slices.
    pub dt_s: f64,
    /// Goals, rad: `q[slice][model joint]` (fixed joints at their angle).
    #[serde(skip)]
    pub q: Vec<Vec<f64>>,
    /// Stance bits per slice (`plan::gait_table::stance_bits`): none suspended, all standing.
    #[serde(skip)]
    pub stance: Vec<u8>,
    pub segments: Vec<Segment>,
}

impl ExcitationTrial {
    /// Number of slices.
    pub fn slices(&self) -> usize {
        self.q.len()
    }

    /// The table's period, s.
    pub fn period_s(&self) -> f64 {
        self.dt_s * self.slices() as f64
    }

    /// The step table of this trial for `model` (no torque bias), built without the board's
    /// rules: `board::rules::build::excitation_table` builds it under them.
    pub fn step_table(&self, model: &Model) -> Result<Vec<u8>, crate::plan::table::TableError> {
        let zeros = vec![vec![0.0; model.joints.len()]; self.slices()];
        // The header's duty factor means nothing here (the firmware does not use it): 0.5.
        crate::plan::gait_table::gait_table(
            model,
            &self.name,
            self.period_s(),
            0.5,
            &self.q,
            &zeros,
            &self.stance,
        )
    }
}

/// An excitation of a model: its trials, each one table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Excitation {
    pub kind: ExcitationKind,
    pub model: String,
    pub options: ExcitationOptions,
    pub trials: Vec<ExcitationTrial>,
}

/// The excitation of `kind` for `model` with `options`.
pub fn excitation(
    model: &Model,
    kind: ExcitationKind,
    options: &ExcitationOptions,
) -> Result<Excitation, ExcitationError> {
    let trials = match kind {
        ExcitationKind::Suspended => suspended(model, options)?,
        ExcitationKind::Standing => vec![standing(model, options)?],
    };
    Ok(Excitation {
        kind,
        model: model.name.clone(),
        options: *options,
        trials,
    })
}

/// The resting posture the excitations start from and return to: the planner's (table 1's body
/// heights, flat ground), the stance the physics robot is set down in.
pub(crate) fn rest(model: &Model) -> Result<crate::kinematics::Posture, KinematicsError> {
    let params = crate::gait::StepParams::table1(&model.name);
    crate::kinematics::resting_posture(model, &crate::terrain::Terrain::Flat, &|leg| {
        params.foot_goal(leg)
    })
}

/// Samples `goal(t)` for each model joint at `n` slices `dt` apart.
pub(crate) fn sample(n: usize, dt: f64, goal: impl Fn(f64) -> Vec<f64>) -> Vec<Vec<f64>> {
    (0..n).map(|s| goal(s as f64 * dt)).collect()
}

/// Slices that cover `total_s` at `dt` (at least 3, so the table loops smoothly).
pub(crate) fn slices_for(total_s: f64, dt: f64) -> usize {
    ((total_s / dt).ceil() as usize).max(3)
}

/// Stance bits of every leg of `model` on the ground.
pub(crate) fn all_stance(model: &Model) -> u8 {
    let legs: Vec<Leg> = model.legs();
    crate::plan::gait_table::stance_bits(&legs, &vec![true; legs.len()])
}

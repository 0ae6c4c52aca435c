//! Stepping parameters (table 1 of the paper) with their defaults and checks.

use super::Gait;
use crate::model::Leg;
use serde::{Deserialize, Serialize};

/// A value per leg pair (hind, middle, front), as table 1 gives them.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PerPair {
    pub hind: f64,
    pub middle: f64,
    pub front: f64,
}

impl PerPair {
    pub const fn all(v: f64) -> PerPair {
        PerPair {
            hind: v,
            middle: v,
            front: v,
        }
    }
    pub fn get(&self, leg: Leg) -> f64 {
        match leg {
            Leg::LH | Leg::RH => self.hind,
            Leg::LM | Leg::RM => self.middle,
            Leg::LF | Leg::RF => self.front,
        }
    }
}

/// Everything that shapes one step cycle.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StepParams {
    /// Swing duration T_sw, s.
    pub swing_s: f64,
    /// Stance duty cycle DS_st, in (0, 1): stance lasts `swing_s * duty / (1 - duty)`.
    pub duty: f64,
    /// Swing apex above the line joining lift-off and touch-down (table 1's h_st), m.
    pub step_height_m: PerPair,
    /// Body translation per step Tr_body: distance the thorax moves during one stance, m
    /// (negative walks backward).
    pub translation_m: f64,
    /// Body yaw per step (during one stance), rad; positive turns left.
    pub rotation_rad: f64,
    /// Body height h_body: foot height below the thorax origin in the resting posture, m.
    pub body_height_m: PerPair,
    pub gait: Gait,
    /// Time slices per step cycle.
    pub slices: usize,
    /// The ground, written as its text in files (see [`crate::terrain::Ground`]).
    pub terrain: crate::terrain::Ground,
    /// Ball radius used for a bare `ball`, m.
    pub ball_radius_m: f64,
    /// Depth of the ball's centre below the centre of mass, for a bare `ball`, m.
    pub ball_offset_m: f64,
    /// Resting foot placement relative to the leg's ThC: forward (x) and outward (|y|) offsets per
    /// leg pair, m. `None`: the feet go wherever the joints are closest to mid-range.
    #[serde(default)]
    pub placement: Option<Placement>,
}

/// Foot placement relative to each ThC in the resting posture, m.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Placement {
    pub forward_m: PerPair,
    pub outward_m: PerPair,
}

/// A stepping parameter that cannot be right.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParamError {
    #[error("parameter `{field}` = {value}: {problem}")]
    Invalid {
        field: &'static str,
        value: String,
        problem: &'static str,
    },
    #[error("{file}: {message}")]
    File { file: String, message: String },
}

impl StepParams {
    /// Table 1 of the paper for a built-in model (Drosophibot II with T_sw = 0.5 s, the MATLAB
    /// solver's default inside table 1's 0.4-1.6 s; Scale-Drosophila as listed). Other models get
    /// Drosophibot II's values.
    pub fn table1(model: &str) -> StepParams {
        match model {
            "scale-drosophila" => StepParams {
                swing_s: 0.1,
                duty: 0.6,
                step_height_m: PerPair::all(0.5e-3),
                translation_m: 0.6e-3,
                rotation_rad: 0.0,
                body_height_m: PerPair::all(1.3e-3),
                gait: Gait::TRIPOD,
                slices: 100,
                terrain: crate::terrain::Ground::Flat,
                // Paper section 3.1: r = 3 mm, centre 3.7 mm below the CoM.
                ball_radius_m: 3e-3,
                ball_offset_m: 3.7e-3,
                // ESTIMATE (the paper's fly stepping data [92] are not available here): chosen by
                // hand so that table 1's steps stay within the .aproj joint limits on flat ground
                // and on the ball; the joints' mid-ranges alone cross the fly's legs.
                placement: Some(Placement {
                    forward_m: PerPair {
                        hind: -0.7e-3,
                        middle: -0.1e-3,
                        front: 0.5e-3,
                    },
                    outward_m: PerPair {
                        hind: 1.2e-3,
                        middle: 1.3e-3,
                        front: 0.6e-3,
                    },
                }),
            },
            _ => StepParams {
                swing_s: 0.5,
                duty: 0.6,
                step_height_m: PerPair {
                    hind: 0.07,
                    middle: 0.05,
                    front: 0.09,
                },
                translation_m: 0.085,
                rotation_rad: 0.0,
                body_height_m: PerPair::all(0.175),
                gait: Gait::TRIPOD,
                slices: 100,
                terrain: crate::terrain::Ground::Flat,
                // Paper section 3.1: r = 0.637 m, centre 0.76 m below the CoM.
                ball_radius_m: 0.637,
                ball_offset_m: 0.76,
                // ESTIMATE, chosen by hand so that table 1's steps stay within the joint limits on
                // flat ground and on the ball (mid-range alone puts the hind feet out of reach on
                // the ball).
                placement: Some(Placement {
                    forward_m: PerPair {
                        hind: -0.10,
                        middle: -0.03,
                        front: 0.0,
                    },
                    outward_m: PerPair {
                        hind: 0.15,
                        middle: 0.17,
                        front: 0.14,
                    },
                }),
            },
        }
    }

    /// Full step period T = T_sw / (1 - duty), s.
    pub fn period_s(&self) -> f64 {
        self.swing_s / (1.0 - self.duty)
    }

    /// Stance duration, s.
    pub fn stance_s(&self) -> f64 {
        self.period_s() * self.duty
    }

    /// Checks every field; the error names the field.
    pub fn validate(&self) -> Result<(), ParamError> {
        let bad = |field, value: f64, problem| ParamError::Invalid {
            field,
            value: value.to_string(),
            problem,
        };
        if !(self.swing_s.is_finite() && self.swing_s > 0.0) {
            return Err(bad(
                "swing_s",
                self.swing_s,
                "swing duration (and so the period) must be > 0",
            ));
        }
        if !(self.duty > 0.0 && self.duty < 1.0) {
            return Err(bad("duty", self.duty, "duty cycle must lie in (0, 1)"));
        }
        // Positive is not enough either: swing 1e-308 s or duty 1e-300 pass the checks above yet
        // give a stance that rounds to 0 s (found by host/planner/tests/integration/reliability_inputs.rs). No bus
        // plays a phase shorter than a millisecond (200 Hz is the fastest rate the board runs).
        const MIN_PHASE_S: f64 = 1e-3;
        if self.swing_s < MIN_PHASE_S {
            return Err(bad(
                "swing_s",
                self.swing_s,
                "swing must last at least 1 ms",
            ));
        }
        // NaN (an invalid duty) is refused here too.
        if self.stance_s().is_nan() || self.stance_s() < MIN_PHASE_S {
            return Err(bad(
                "duty",
                self.duty,
                "the stance swing_s * duty / (1 - duty) must last at least 1 ms",
            ));
        }
        for (f, p) in [
            ("step_height_m", &self.step_height_m),
            ("body_height_m", &self.body_height_m),
        ] {
            for v in [p.hind, p.middle, p.front] {
                if !(v.is_finite() && v > 0.0) {
                    return Err(bad(f, v, "must be > 0"));
                }
            }
        }
        if !self.translation_m.is_finite() {
            return Err(bad("translation_m", self.translation_m, "not finite"));
        }
        if !(self.rotation_rad.is_finite() && self.rotation_rad.abs() < std::f64::consts::PI) {
            return Err(bad(
                "rotation_rad",
                self.rotation_rad,
                "must be finite and below pi per step",
            ));
        }
        if self.slices < 4 {
            return Err(bad(
                "slices",
                self.slices as f64,
                "need at least 4 slices per step",
            ));
        }
        if !(self.gait.phi_i.is_finite() && self.gait.phi_c.is_finite()) {
            return Err(bad("gait", self.gait.phi_i, "phase offsets must be finite"));
        }
        if !(self.ball_radius_m.is_finite() && self.ball_radius_m > 0.0) {
            return Err(bad("ball_radius_m", self.ball_radius_m, "must be > 0"));
        }
        if !self.ball_offset_m.is_finite() {
            return Err(bad("ball_offset_m", self.ball_offset_m, "not finite"));
        }
        // Finite is not enough: the footpath quintics raise times to the 5th power and lengths
        // near f64::MAX overflow to infinity (found by host/planner/tests/integration/reliability_inputs.rs). These
        // bounds are far beyond any walking robot and only keep the arithmetic finite.
        const MAX_LENGTH_M: f64 = 100.0;
        const MAX_PERIOD_S: f64 = 3600.0;
        if self.period_s() > MAX_PERIOD_S {
            return Err(bad(
                "duty",
                self.duty,
                "the step period swing_s / (1 - duty) must be at most 3600 s",
            ));
        }
        let mut lengths = vec![
            ("translation_m", self.translation_m),
            ("ball_radius_m", self.ball_radius_m),
            ("ball_offset_m", self.ball_offset_m),
        ];
        for (f, p) in [
            ("step_height_m", &self.step_height_m),
            ("body_height_m", &self.body_height_m),
        ] {
            lengths.extend([(f, p.hind), (f, p.middle), (f, p.front)]);
        }
        if let Some(pl) = &self.placement {
            for (f, p) in [
                ("placement.forward_m", &pl.forward_m),
                ("placement.outward_m", &pl.outward_m),
            ] {
                lengths.extend([(f, p.hind), (f, p.middle), (f, p.front)]);
            }
        }
        for (f, v) in lengths {
            if !(v.is_finite() && v.abs() <= MAX_LENGTH_M) {
                return Err(bad(f, v, "must be finite and at most 100 m"));
            }
        }
        Ok(())
    }
}

/// A parameter file: any subset of [`StepParams`] fields, the rest from table 1.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParamsFile {
    pub swing_s: Option<f64>,
    pub duty: Option<f64>,
    pub step_height_m: Option<PerPair>,
    pub translation_m: Option<f64>,
    pub rotation_rad: Option<f64>,
    pub body_height_m: Option<PerPair>,
    pub gait: Option<Gait>,
    pub slices: Option<usize>,
    pub terrain: Option<crate::terrain::Ground>,
    pub ball_radius_m: Option<f64>,
    pub ball_offset_m: Option<f64>,
    pub placement: Option<Placement>,
}

impl ParamsFile {
    /// Parses TOML text; `file` names it in errors.
    pub fn from_toml(text: &str, file: &str) -> Result<ParamsFile, ParamError> {
        toml::from_str(text).map_err(|e| ParamError::File {
            file: file.to_string(),
            message: e.to_string(),
        })
    }

    /// Overrides `base` with every field given here.
    pub fn apply(&self, base: &mut StepParams) {
        macro_rules! set {
            ($($f:ident),*) => { $( if let Some(v) = self.$f.clone() { base.$f = v; } )* };
        }
        set!(
            swing_s,
            duty,
            step_height_m,
            translation_m,
            rotation_rad,
            body_height_m,
            gait,
            slices,
            terrain,
            ball_radius_m,
            ball_offset_m
        );
        if self.placement.is_some() {
            base.placement = self.placement;
        }
    }
}

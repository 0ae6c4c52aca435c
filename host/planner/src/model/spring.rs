//! Parallel elasticity (paper sections 2.2.2 and 3.1.2): a spring beside a joint's actuator.
//!
//! Names used everywhere (code, plan.json, docs): the *actuator stiffness* is the proportional
//! gain of the servo (or muscle) in N m/rad, the *parallel spring stiffness* is the spring's
//! alone, and the *joint stiffness* is their sum, the k of V* = 1/2 sum T_act^2 / k (eq. 9).
//! The step table and the servo-command bias use the actuator stiffness only: the spring does not
//! move with the command.

use super::{Actuation, EquilibriumSource, JointKind, Model, ParallelSpring};
use serde::{Deserialize, Serialize};

/// The stiffest parallel spring `--spring` accepts, N m/rad: the model's own bound.
const MAX_STIFFNESS: f64 = super::ranges::STIFFNESS_NM_PER_RAD.1;

/// The paper's parallel stiffness values (section 3.1.2), as named presets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpringPreset {
    /// 1 N m/rad on every joint of Drosophibot II: "selected such that the resulting torques at
    /// each DoF would not overload our selected actuators".
    Drosophibot2,
    /// 3.8e-8 N m/rad on every joint of Scale-Drosophila, "calculated based on dynamic scaling
    /// calculations presented in [91]".
    ScaleDrosophila,
}

impl SpringPreset {
    pub const ALL: [SpringPreset; 2] = [SpringPreset::Drosophibot2, SpringPreset::ScaleDrosophila];

    /// The preset's name, the built-in model's name it belongs to.
    pub fn name(self) -> &'static str {
        match self {
            SpringPreset::Drosophibot2 => "drosophibot2",
            SpringPreset::ScaleDrosophila => "scale-drosophila",
        }
    }

    /// Parallel spring stiffness, N m/rad.
    pub fn stiffness(self) -> f64 {
        match self {
            SpringPreset::Drosophibot2 => 1.0,
            SpringPreset::ScaleDrosophila => 3.8e-8,
        }
    }

    /// Where the value comes from.
    pub fn source(self) -> &'static str {
        match self {
            SpringPreset::Drosophibot2 => {
                "paper section 3.1.2 (k_joint = 1 N m/rad, Drosophibot II)"
            }
            SpringPreset::ScaleDrosophila => {
                "paper section 3.1.2 (k_joint = 3.8e-8 N m/rad, Scale-Drosophila, from the dynamic scaling of its ref. [91])"
            }
        }
    }

    /// The preset of a built-in model's name, if it has one.
    pub fn for_model(model_name: &str) -> Option<SpringPreset> {
        SpringPreset::ALL
            .into_iter()
            .find(|p| p.name() == model_name)
    }
}

/// What `--spring` asks for on a whole model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SpringSpec {
    /// Remove every parallel spring.
    None,
    /// The paper's value for this model (by its name).
    Paper,
    Preset(SpringPreset),
    /// This parallel stiffness on every actuated joint, N m/rad.
    Stiffness(f64),
}

/// In words, as `--spring` takes it: `no springs`, `the paper's springs`, `springs of 1 N m/rad`.
impl std::fmt::Display for SpringSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SpringSpec::None => f.write_str("no parallel springs"),
            SpringSpec::Paper => f.write_str("the paper's parallel springs"),
            SpringSpec::Preset(p) => write!(
                f,
                "the {} parallel springs ({} N m/rad)",
                p.name(),
                p.stiffness()
            ),
            SpringSpec::Stiffness(k) => write!(f, "parallel springs of {k} N m/rad"),
        }
    }
}

/// A `--spring` value that is not understood, or has no value for the model.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SpringError {
    #[error(
        "spring `{spec}`: expected none, paper, drosophibot2, scale-drosophila or a stiffness >= 0 in N m/rad"
    )]
    Unknown { spec: String },
    /// A stiffness beyond the range every model's parallel spring must lie in
    /// ([`super::ranges::STIFFNESS_NM_PER_RAD`]): the planner's posture solve does not converge
    /// under such a spring (`1e300` ran for hours).
    #[error(
        "spring `{spec}`: {value:e} N m/rad is outside the range of a parallel stiffness, 0 ..= {max:e} N m/rad"
    )]
    OutOfRange { spec: String, value: f64, max: f64 },
    #[error(
        "spring `paper`: the paper gives no parallel stiffness for model `{model}` (it has values for drosophibot2 and scale-drosophila); give one in N m/rad"
    )]
    NoPaperValue { model: String },
}

impl SpringSpec {
    /// Parses `none`, `paper`, a preset name or a stiffness in N m/rad.
    pub fn parse(spec: &str) -> Result<SpringSpec, SpringError> {
        let unknown = || SpringError::Unknown {
            spec: spec.to_string(),
        };
        match spec {
            "none" => Ok(SpringSpec::None),
            "paper" => Ok(SpringSpec::Paper),
            _ => match SpringPreset::ALL.into_iter().find(|p| p.name() == spec) {
                Some(p) => Ok(SpringSpec::Preset(p)),
                None => match spec.parse::<f64>() {
                    Ok(k) if (0.0..=MAX_STIFFNESS).contains(&k) => Ok(SpringSpec::Stiffness(k)),
                    Ok(k) if k > MAX_STIFFNESS => Err(SpringError::OutOfRange {
                        spec: spec.to_string(),
                        value: k,
                        max: MAX_STIFFNESS,
                    }),
                    _ => Err(unknown()),
                },
            },
        }
    }

    /// The parallel stiffness this asks for on `model` (0: no springs).
    pub fn stiffness(&self, model: &Model) -> Result<f64, SpringError> {
        match self {
            SpringSpec::None => Ok(0.0),
            SpringSpec::Paper => SpringPreset::for_model(&model.name)
                .map(SpringPreset::stiffness)
                .ok_or_else(|| SpringError::NoPaperValue {
                    model: model.name.clone(),
                }),
            SpringSpec::Preset(p) => Ok(p.stiffness()),
            SpringSpec::Stiffness(k) => Ok(*k),
        }
    }

    /// `model` with this spring on every actuated joint (equilibrium from `from`), or with no
    /// springs at all for a stiffness of zero.
    pub fn apply(&self, model: &Model, from: EquilibriumSource) -> Result<Model, SpringError> {
        Ok(with_parallel_springs(model, self.stiffness(model)?, from))
    }
}

/// `model` with a parallel spring of `stiffness` (N m/rad) on every actuated joint; fixed joints
/// get none. A stiffness of zero removes all springs.
pub fn with_parallel_springs(model: &Model, stiffness: f64, from: EquilibriumSource) -> Model {
    let mut m = model.clone();
    for j in &mut m.joints {
        j.spring = match (&j.actuation, stiffness > 0.0) {
            (Actuation::Actuated { .. }, true) => Some(ParallelSpring {
                stiffness,
                equilibrium: 0.5 * (j.limits.0 + j.limits.1),
                equilibrium_from: from,
            }),
            (Actuation::Actuated { .. }, false) | (Actuation::Fixed { .. }, _) => None,
        };
    }
    m
}

/// The original solver's dead-fly CTr equilibrium, rad: "CTr about -35 deg"
/// (`../shared/reference/solver.md`, "Parallel springs"; the paper, section 2.2.1, gives no angle).
pub const DEAD_FLY_CTR_RAD: f64 = -35.0 * std::f64::consts::PI / 180.0;
/// How far below its smallest angle over the step the dead-fly FTi rests, rad: "FTi about its
/// minimum angle - 20 deg" (same source), read as the step's minimum (the paper derives the
/// equilibria "using the full ROM over the step").
pub const DEAD_FLY_FTI_BELOW_MIN_RAD: f64 = 20.0 * std::f64::consts::PI / 180.0;

/// The dead-fly proxy's equilibrium of a joint of `kind` whose angles over the step span
/// `lo..=hi` rad: CTr [`DEAD_FLY_CTR_RAD`], FTi `lo - `[`DEAD_FLY_FTI_BELOW_MIN_RAD`], any other
/// joint the middle of its range over the step. A proxy, not the paper's angles (it does not list
/// them).
pub fn dead_fly_equilibrium(kind: JointKind, lo: f64, hi: f64) -> f64 {
    match kind {
        JointKind::CTr => DEAD_FLY_CTR_RAD,
        JointKind::FTi => lo - DEAD_FLY_FTI_BELOW_MIN_RAD,
        _ => 0.5 * (lo + hi),
    }
}

/// Sets the equilibrium of every spring that takes it from the plan: the resting posture's angle
/// `rest[j]`, the middle of the joint's range over the step's angles `q[slice][j]`, or the
/// dead-fly proxy ([`dead_fly_equilibrium`]).
pub fn resolve_equilibria(model: &mut Model, rest: &[f64], q: &[Vec<f64>]) {
    for (j, joint) in model.joints.iter_mut().enumerate() {
        let kind = joint.kind;
        if let Some(s) = &mut joint.spring {
            let range = || {
                q.iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), r| {
                        (l.min(r[j]), h.max(r[j]))
                    })
            };
            match s.equilibrium_from {
                EquilibriumSource::Given => {}
                EquilibriumSource::RestingPosture => s.equilibrium = rest[j],
                EquilibriumSource::StepMidrange => {
                    let (lo, hi) = range();
                    if lo <= hi {
                        s.equilibrium = 0.5 * (lo + hi);
                    }
                }
                EquilibriumSource::DeadFly => {
                    let (lo, hi) = range();
                    if lo <= hi {
                        s.equilibrium = dead_fly_equilibrium(kind, lo, hi);
                    }
                }
            }
        }
    }
}

/// Reads a model file's spring entry; `limits` are the joint's (placeholder equilibrium until a
/// plan resolves it). The error is the field and the problem.
pub(crate) fn from_entry(
    s: &SpringEntry,
    limits: (f64, f64),
) -> Result<ParallelSpring, (&'static str, String)> {
    if !(s.stiffness_nm_per_rad.is_finite() && s.stiffness_nm_per_rad >= 0.0) {
        return Err(("spring.stiffness_nm_per_rad", "must be >= 0".into()));
    }
    let (equilibrium, equilibrium_from) = match (s.equilibrium_rad, s.equilibrium) {
        (Some(_), Some(_)) => {
            return Err((
                "spring.equilibrium",
                "give either equilibrium_rad or equilibrium, not both".into(),
            ));
        }
        (Some(e), None) if !e.is_finite() => {
            return Err(("spring.equilibrium_rad", "not finite".into()));
        }
        (Some(e), None) => (e, EquilibriumSource::Given),
        (None, from) => (
            0.5 * (limits.0 + limits.1),
            match from {
                None | Some(EquilibriumEntry::Rest) => EquilibriumSource::RestingPosture,
                Some(EquilibriumEntry::StepMidrange) => EquilibriumSource::StepMidrange,
                Some(EquilibriumEntry::DeadFly) => EquilibriumSource::DeadFly,
            },
        ),
    };
    Ok(ParallelSpring {
        stiffness: s.stiffness_nm_per_rad,
        equilibrium,
        equilibrium_from,
    })
}

/// The model file's entry of a spring (an equilibrium from the plan is written as its source).
pub(crate) fn to_entry(s: &ParallelSpring) -> SpringEntry {
    let (equilibrium_rad, equilibrium) = match s.equilibrium_from {
        EquilibriumSource::Given => (Some(s.equilibrium), None),
        EquilibriumSource::RestingPosture => (None, Some(EquilibriumEntry::Rest)),
        EquilibriumSource::StepMidrange => (None, Some(EquilibriumEntry::StepMidrange)),
        EquilibriumSource::DeadFly => (None, Some(EquilibriumEntry::DeadFly)),
    };
    SpringEntry {
        stiffness_nm_per_rad: s.stiffness,
        equilibrium_rad,
        equilibrium,
    }
}

/// A joint's `spring` entry in a model file (TOML).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpringEntry {
    /// Parallel spring stiffness alone (the actuator's is the joint's `stiffness_nm_per_rad`).
    pub stiffness_nm_per_rad: f64,
    /// Equilibrium angle (rad); when absent, `equilibrium` says where it comes from.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub equilibrium_rad: Option<f64>,
    /// `rest` (default: the plan's resting posture), `step_midrange` (the middle of the joint's
    /// range over the planned step) or `dead_fly` (the newly-dead-fly proxy,
    /// [`crate::model::spring::dead_fly_equilibrium`]); only without `equilibrium_rad`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub equilibrium: Option<EquilibriumEntry>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EquilibriumEntry {
    Rest,
    StepMidrange,
    DeadFly,
}

//! The `dynamics` object of plan.json, typed: the stiffness per joint, V* per slice, the options
//! the cycle was solved with, and its slips and saturations.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::{CycleSolution, DynamicsOptions};
use crate::model::{Actuation, EquilibriumSource, Model};

/// What `stiffness` means in [`DynamicsSummary`].
pub const STIFFNESS_NOTE: &str = "joint stiffness k = actuator stiffness + parallel spring stiffness, used in V* = 1/2 sum T_act^2 / k; the servo-command bias and the step table use the actuator stiffness alone";

/// A solved cycle as plan.json records it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DynamicsSummary {
    /// Per actuated joint, the stiffness of V*, N m/rad.
    pub joint_stiffness_nm_per_rad: BTreeMap<String, f64>,
    /// Per actuated joint, the servo's proportional stiffness, N m/rad.
    pub actuator_stiffness_nm_per_rad: BTreeMap<String, f64>,
    /// Per joint with a parallel spring, that spring.
    pub parallel_spring: BTreeMap<String, SpringSummary>,
    /// [`STIFFNESS_NOTE`].
    pub stiffness_note: String,
    /// V* per slice, J.
    pub v_star_j: Vec<f64>,
    /// The largest actuated torque of the cycle, N m.
    pub peak_abs_torque_nm: f64,
    pub friction_cone: bool,
    pub push_only: bool,
    /// The friction coefficient of the cone and of the slip report.
    pub mu: f64,
    pub torque_limits_enforced: bool,
    pub slips: Vec<SlipSummary>,
    pub saturations: Vec<SaturationSummary>,
}

/// A parallel spring on one joint.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpringSummary {
    pub stiffness_nm_per_rad: f64,
    pub equilibrium_rad: f64,
    pub equilibrium_from: EquilibriumSource,
}

/// A stance foot outside the friction cone or pulling, in one slice.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SlipSummary {
    pub slice: usize,
    pub leg: String,
    pub normal_n: f64,
    pub tangential_n: f64,
}

/// An actuated joint over its torque limit, in one slice.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SaturationSummary {
    pub slice: usize,
    pub joint: String,
    pub torque_nm: f64,
    pub limit_nm: f64,
}

impl DynamicsSummary {
    /// The summary of `cycle`, solved for `model` with `options`.
    pub fn new(model: &Model, options: &DynamicsOptions, cycle: &CycleSolution) -> Self {
        let joint_stiffness_nm_per_rad = model
            .joints
            .iter()
            .zip(&cycle.stiffness)
            .filter_map(|(j, k)| k.map(|k| (j.name.clone(), k)))
            .collect();
        let actuator_stiffness_nm_per_rad = model
            .joints
            .iter()
            .filter_map(|j| match j.actuation {
                Actuation::Actuated { stiffness, .. } => Some((j.name.clone(), stiffness)),
                Actuation::Fixed { .. } => None,
            })
            .collect();
        let parallel_spring = model
            .joints
            .iter()
            .filter_map(|j| {
                j.spring.as_ref().map(|s| {
                    let spring = SpringSummary {
                        stiffness_nm_per_rad: s.stiffness,
                        equilibrium_rad: s.equilibrium,
                        equilibrium_from: s.equilibrium_from,
                    };
                    (j.name.clone(), spring)
                })
            })
            .collect();
        let peak_abs_torque_nm = cycle
            .slices
            .iter()
            .flat_map(|s| s.torque.iter())
            .fold(0.0f64, |m, t| m.max(t.abs()));
        DynamicsSummary {
            joint_stiffness_nm_per_rad,
            actuator_stiffness_nm_per_rad,
            parallel_spring,
            stiffness_note: STIFFNESS_NOTE.to_string(),
            v_star_j: cycle.slices.iter().map(|s| s.v_star).collect(),
            peak_abs_torque_nm,
            friction_cone: options.friction_cone,
            push_only: options.push_only,
            mu: options.mu,
            torque_limits_enforced: options.enforce_torque_limits,
            slips: cycle
                .report
                .slips
                .iter()
                .map(|s| SlipSummary {
                    slice: s.slice,
                    leg: s.leg.clone(),
                    normal_n: s.normal,
                    tangential_n: s.tangential,
                })
                .collect(),
            saturations: cycle
                .report
                .saturations
                .iter()
                .map(|s| SaturationSummary {
                    slice: s.slice,
                    joint: s.joint.clone(),
                    torque_nm: s.torque,
                    limit_nm: s.limit,
                })
                .collect(),
        }
    }
}

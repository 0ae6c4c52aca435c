//! Strain per slice and gauge of a solved cycle: the section wrench by the distal free body,
//! resolved into microstrain.

use super::StrainError;
use super::cut::{Site, SliceBodies, distal_wrench, in_section_frame};
use super::section::{SectionWrench, gauge_strain};
use crate::dynamics::{CycleSolution, SliceInput, plan_inputs};
use crate::model::Model;
use crate::plan::Plan;

/// One gauge in one slice.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaugeReading {
    /// Predicted reading, microstrain (1e-6; tension positive).
    pub microstrain: f64,
    /// The section wrench behind it, section frame (N, N m).
    pub wrench: SectionWrench,
}

/// Predicted readings of every gauge of a model over a cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct StrainPrediction {
    /// `readings[slice][gauge]`, gauges in `model.gauges` order.
    pub readings: Vec<Vec<GaugeReading>>,
}

impl StrainPrediction {
    /// `microstrain[slice][gauge]`.
    pub fn microstrain(&self) -> Vec<Vec<f64>> {
        self.readings
            .iter()
            .map(|s| s.iter().map(|r| r.microstrain).collect())
            .collect()
    }
}

/// The readings of `model.gauges` in every slice of `cycle`, solved from `inputs`.
pub fn predict(
    model: &Model,
    inputs: &[SliceInput],
    cycle: &CycleSolution,
) -> Result<StrainPrediction, StrainError> {
    if inputs.len() != cycle.slices.len() {
        return Err(StrainError::Slices {
            inputs: inputs.len(),
            solved: cycle.slices.len(),
        });
    }
    let sites = sites(model)?;
    let readings = inputs
        .iter()
        .zip(&cycle.slices)
        .map(|(input, sol)| slice_readings(model, &sites, input, &sol.grf))
        .collect();
    Ok(StrainPrediction { readings })
}

/// The cut of every gauge of `model`, in `model.gauges` order.
pub fn sites(model: &Model) -> Result<Vec<Site>, StrainError> {
    model.gauges.iter().map(|g| Site::of(model, g)).collect()
}

/// The readings of every gauge (`sites` from [`sites`]) in one state `input` with the ground
/// reaction forces `grf` (thorax frame, per foot): the planner's prediction with the solver's
/// GRF, the physics robot's simulated gauges with MuJoCo's state and contact forces.
pub fn slice_readings(
    model: &Model,
    sites: &[Site],
    input: &SliceInput,
    grf: &[nalgebra::Vector3<f64>],
) -> Vec<GaugeReading> {
    let bodies = SliceBodies::of(model, input);
    model
        .gauges
        .iter()
        .zip(sites)
        .map(|(g, site)| {
            let frame = site.frame(g, &bodies.motions[site.segment]);
            let w = distal_wrench(model, site, &frame, &bodies, grf);
            let wrench = in_section_frame(&frame, &w);
            GaugeReading {
                microstrain: 1e6 * gauge_strain(g.direction, &g.section, &g.material, &wrench),
                wrench,
            }
        })
        .collect()
}

/// [`predict`] for a plan and its solved cycle.
pub fn predict_plan(plan: &Plan, cycle: &CycleSolution) -> Result<StrainPrediction, StrainError> {
    predict(&plan.model, &plan_inputs(plan), cycle)
}

//! How far the feet of a steering blend are from a planned foot path. The board steers by blending,
//! joint by joint at the same slice, the angles of a straight gait and a turning one
//! (`protocol::steer`); the gait planned directly for the blended heading is another footpath. This
//! measures the gap: forward kinematics (`planner::kinematics::forward`) of the blended angles
//! against forward kinematics of the angles planned for heading `w x range` (heading = the body's
//! yaw per stance, `StepParams::rotation_rad`), the largest foot distance over every slice and leg.

use planner::gait::StepParams;
use planner::kinematics::forward;
use planner::model::Model;
use planner::plan::{Plan, plan};

use crate::error::{Context, Result};

/// The gap of one blend.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlendGap {
    /// Share of the turning gait in the blend (0 straight, 1 the turn).
    pub weight: f64,
    /// The heading the blend stands for, rad of yaw per stance.
    pub heading_rad: f64,
    /// Largest distance of a blended foot from the planned one over the step, mm.
    pub max_mm: f64,
    /// Its slice and leg name.
    pub slice: usize,
    pub leg: &'static str,
}

fn feet(model: &Model, q: &[f64]) -> Vec<nalgebra::Point3<f64>> {
    forward(model, q).feet
}

/// The gaps of blends at `weights` of the straight gait of `base` (its rotation set to 0) and the
/// one turning `range_rad` per stance, each against the gait planned for `weight x range_rad`.
pub fn blend_gaps(
    model: &Model,
    base: &StepParams,
    range_rad: f64,
    weights: &[f64],
) -> Result<Vec<BlendGap>> {
    let plan_at = |rot: f64| -> Result<Plan> {
        let p = StepParams {
            rotation_rad: rot,
            ..base.clone()
        };
        plan(model, &p).with_context(|| format!("planning a turn of {rot} rad per stance"))
    };
    let straight = plan_at(0.0)?;
    let turn = plan_at(range_rad)?;
    let mut out = Vec::with_capacity(weights.len());
    for &w in weights {
        let direct = plan_at(w * range_rad)?;
        let mut gap = BlendGap {
            weight: w,
            heading_rad: w * range_rad,
            max_mm: 0.0,
            slice: 0,
            leg: "",
        };
        for s in 0..straight.slices() {
            let q: Vec<f64> = straight.q[s]
                .iter()
                .zip(&turn.q[s])
                .map(|(a, b)| a + w * (b - a))
                .collect();
            let blended = feet(model, &q);
            let planned = feet(model, &direct.q[s]);
            for (f, (a, b)) in blended.iter().zip(&planned).enumerate() {
                let d = (a - b).norm() * 1000.0;
                if d > gap.max_mm {
                    gap.max_mm = d;
                    gap.slice = s;
                    gap.leg = model.feet[f].leg.name();
                }
            }
        }
        out.push(gap);
    }
    Ok(out)
}

/// The validation block: Drosophibot II at the default preset, 40 slices, a family over
/// [`RANGE_RAD`] of yaw per stance, blends at a quarter, half and three quarters.
pub fn block() -> Result<String> {
    let model = planner::model::builtin("drosophibot2")?;
    let mut base = StepParams::preset(planner::gait::DEFAULT_PRESET, &model.name)
        .context("the default preset")?;
    base.slices = 40;
    let gaps = blend_gaps(&model, &base, RANGE_RAD, &[0.25, 0.5, 0.75])?;
    let mut s = format!(
        "Drosophibot II, preset {}, {} slices, turning gait {RANGE_RAD} rad of yaw per stance:",
        planner::gait::DEFAULT_PRESET,
        base.slices
    );
    for g in &gaps {
        s.push_str(&format!(
            " blend {:.2} (heading {:.3} rad): at most {:.2} mm ({} at slice {});",
            g.weight, g.heading_rad, g.max_mm, g.leg, g.slice
        ));
    }
    s.pop();
    s.push('.');
    Ok(s)
}

/// The turning gait of [`block`]'s family, rad of yaw per stance: about the largest turn whose
/// slice 0 the board's switch rule admits next to the straight gait's at 100 Hz (measured: the
/// joints' slice-0 angles differ by 0.155 rad at a 0.2 rad turn, roughly in proportion to the turn,
/// against the MX-28's 0.0576 rad per bus cycle; ESTIMATE of the proportion).
pub const RANGE_RAD: f64 = 0.06;

//! Named stepping-parameter presets beyond table 1: the default walk the servos can follow
//! (`servo-safe`), the posture the original solver gave the physical Drosophibot II (`../shared/reference/solver.md`, "Resting posture of the physical
//! robot"), and the paper's comparison conditions.
//!
//! The original method places each resting foot at the leg pair's ground height, x and y relative
//! to the ThC, with the joints as near mid-range as that allows; [`crate::kinematics::resting_posture`]
//! does the same with a [`Placement`]. Only the numbers differ: table 1's built-in placement is a
//! hand-chosen estimate that also reaches the ball; `physical-robot` takes the original's figure.

use super::{PerPair, Placement, StepParams};

/// Preset names accepted by [`StepParams::preset`]; the first is `dbot plan`'s default.
pub const PRESETS: [&str; 4] = ["servo-safe", "table1", "physical-robot", "paper-comparison"];

/// The preset a plan starts from when none is named: `dbot plan --preset`'s default and Python's
/// `dbot.plan(model)` (python/src/plan.rs) both read it, so the two cannot drift apart.
pub const DEFAULT_PRESET: &str = PRESETS[0];

/// Swing duration of the `servo-safe` preset, s: table 1 allows 0.4 to 1.6 s. It is the shortest
/// swing at which every Drosophibot II joint keeps at least 25 % of its servo's no-load speed in
/// reserve on flat ground and on the ball (the front FTi on the ball is the fastest joint; at the
/// original solver's 0.5 s it is over its no-load speed). The reserve is for what the datasheet's
/// no-load speed leaves out: a loaded servo turns slower (the torque-speed line) and its position
/// loop lags. The shares are measured by `dbot validate` (docs/validation.md, the generated
/// `feasibility` and `swing-choice` blocks, regenerated and checked by the `validation_doc` test),
/// and the default is tested by host/planner/tests/integration/plan_default_feasible.rs.
pub const SERVO_SAFE_SWING_S: f64 = 1.0;

impl StepParams {
    /// A named preset for a model: `servo-safe` (table 1 at swing [`SERVO_SAFE_SWING_S`] on
    /// Drosophibot II and other robot models, which their servos can follow; scale-drosophila,
    /// whose actuators are not servos, gets its table 1 unchanged); `table1` ([`StepParams::table1`]); `physical-robot`
    /// (Drosophibot II as the original solver ran it: per-pair body heights, table 1's note, and
    /// the resting feet of its posture figure, at table 1's longest swing 1.6 s); `paper-comparison`
    /// (section 3.1: table 1 at the robot's 4 s period or the fly's table 1 swing, see
    /// [`crate::analysis::paper`]). `None` for an unknown name, or `physical-robot` on a model
    /// other than drosophibot2.
    pub fn preset(name: &str, model: &str) -> Option<StepParams> {
        let mut p = StepParams::table1(model);
        match name {
            "table1" => {}
            "servo-safe" => {
                if model != "scale-drosophila" {
                    p.swing_s = SERVO_SAFE_SWING_S;
                }
            }
            "paper-comparison" => {
                p.swing_s = if model == "scale-drosophila" {
                    crate::analysis::paper::FLY_SWING_S
                } else {
                    crate::analysis::paper::ROBOT_SWING_S
                };
            }
            "physical-robot" if model == "drosophibot2" => {
                // solver.md: ThC -> foot offsets (x, |y|, z) = (-0.150, 0.130, -0.150) hind,
                // (-0.025, 0.200, -0.165) middle, (0.114, 0.065, -0.203) m front; feet at
                // z = -0.175 / -0.190 / -0.165 m below that figure's thorax origin. Its thorax
                // origin sits 0.0196 m higher relative to the ThCs than ours (ThC z -0.0246 and
                // 0.0377 m there, -0.0050 and 0.0573 m in host/planner/models/drosophibot2.toml), so the
                // body heights here are the original's minus 0.0196 m: the feet then land at the
                // original's offsets from each ThC in x, y and z.
                p.swing_s = 1.6;
                p.body_height_m = PerPair {
                    hind: 0.175 - 0.0196,
                    middle: 0.190 - 0.0196,
                    front: 0.165 - 0.0196,
                };
                p.placement = Some(Placement {
                    forward_m: PerPair {
                        hind: -0.150,
                        middle: -0.025,
                        front: 0.114,
                    },
                    outward_m: PerPair {
                        hind: 0.130,
                        middle: 0.200,
                        front: 0.065,
                    },
                });
            }
            _ => return None,
        }
        Some(p)
    }
}

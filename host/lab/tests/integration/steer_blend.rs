//! The steering blend's feet against planned foot paths (`lab::steer_blend`): exact at the
//! family's own gaits (weight 0 and 1 are those plans' angles, so forward kinematics must agree
//! to rounding), within a bound in between, and far closer to the planned path than the straight
//! gait's feet are to the turn's (so the blend does follow the heading's path, not just one end).

use lab::steer_blend::{RANGE_RAD, blend_gaps};
use planner::gait::{DEFAULT_PRESET, StepParams};
use planner::kinematics::forward;
use planner::model::builtin;

/// The bound docs/validation.md states for a blend's foot against the planned foot path, mm
/// (measured: 0.06 mm at half the 0.06 rad family, 0.7 mm at half a 0.2 rad one).
const BOUND_MM: f64 = 1.0;

#[test]
fn blended_feet_stay_within_a_millimetre_of_the_planned_foot_path() {
    let model = builtin("drosophibot2").unwrap();
    let mut base = StepParams::preset(DEFAULT_PRESET, &model.name).unwrap();
    base.slices = 40;
    let gaps = blend_gaps(&model, &base, RANGE_RAD, &[0.0, 0.5, 1.0]).unwrap();
    assert!(gaps[0].max_mm < 1e-9 && gaps[2].max_mm < 1e-9, "{gaps:?}");
    assert!(gaps[1].max_mm < BOUND_MM, "{:?}", gaps[1]);
    // The straight and the turning gait's feet, for scale.
    let plan = |r: f64| {
        planner::plan::plan(
            &model,
            &StepParams {
                rotation_rad: r,
                ..base.clone()
            },
        )
        .unwrap()
    };
    let (s, t) = (plan(0.0), plan(RANGE_RAD));
    let mut apart = 0.0f64;
    for k in 0..s.slices() {
        let (a, b) = (forward(&model, &s.q[k]).feet, forward(&model, &t.q[k]).feet);
        for (x, y) in a.iter().zip(&b) {
            apart = apart.max((x - y).norm() * 1000.0);
        }
    }
    assert!(
        gaps[1].max_mm < apart / 10.0,
        "{:?} against {apart:.1} mm",
        gaps[1]
    );
    // The family the board can blend: the same legs in stance in every slice.
    assert_eq!(s.stance, t.stance);
}

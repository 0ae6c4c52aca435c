//! The `physical-robot` preset lands Drosophibot II's resting feet where the original solver put
//! them (`../shared/reference/solver.md`, "Resting posture of the physical robot": ThC -> foot
//! offsets and foot heights read from its posture figure), with the joints within their limits.

use planner::gait::StepParams;
use planner::model::{Leg, builtin};

/// (leg pair, ThC -> foot x, |y|, z), solver.md's table (z: foot z minus ThC z of that table).
const ORIGINAL: [(&str, f64, f64, f64); 3] = [
    ("hind", -0.150, 0.130, -0.175 + 0.0246),
    ("middle", -0.025, 0.200, -0.190 + 0.0246),
    ("front", 0.114, 0.065, -0.165 - 0.0377),
];

fn pair(leg: Leg) -> &'static str {
    match leg {
        Leg::LF | Leg::RF => "front",
        Leg::LM | Leg::RM => "middle",
        Leg::LH | Leg::RH => "hind",
    }
}

#[test]
fn physical_robot_feet_land_where_the_original_put_them() {
    let model = builtin("drosophibot2").unwrap();
    let p = StepParams::preset("physical-robot", "drosophibot2").unwrap();
    let terrain = p
        .terrain
        .plan_terrain(p.ball_radius_m, p.ball_offset_m)
        .unwrap();
    let posture =
        planner::kinematics::resting_posture(&model, &terrain, &|leg| p.foot_goal(leg)).unwrap();
    for (leg, foot) in &posture.feet {
        let thc = model.joints[model.leg_chain(*leg)[0]]
            .origin
            .translation
            .vector;
        let (_, x, y, z) = ORIGINAL.iter().find(|o| o.0 == pair(*leg)).unwrap();
        let got = (
            foot.x - thc.x,
            leg.side() * (foot.y - thc.y),
            foot.z - thc.z,
        );
        // x and y are placed exactly; z to the 0.1 mm that the model's left and right ThC
        // heights differ by.
        assert!(
            (got.0 - x).abs() < 1e-6 && (got.1 - y).abs() < 1e-6 && (got.2 - z).abs() < 2e-4,
            "{leg:?}: ThC -> foot ({:.4}, {:.4}), z {:.4}; the original ({x}, {y}), z {z}",
            got.0,
            got.1,
            got.2
        );
    }
    for (j, joint) in model.joints.iter().enumerate() {
        let q = posture.q[j];
        assert!(
            joint.limits.0 - 1e-9 <= q && q <= joint.limits.1 + 1e-9,
            "{} at {q} outside {:?}",
            joint.name,
            joint.limits
        );
    }
    // At the preset's 4 s period the walk stays within the servos' limits.
    let plan = planner::plan::plan(&model, &p).unwrap();
    let f = planner::plan::feasibility::check(&plan.model, &plan.q, None, plan.dt);
    assert!(f.is_feasible(), "{:?}", f.violations);
}

#[test]
fn unknown_presets_are_refused() {
    assert!(StepParams::preset("physical-robot", "scale-drosophila").is_none());
    assert!(StepParams::preset("fast", "drosophibot2").is_none());
    let p = StepParams::preset("paper-comparison", "drosophibot2").unwrap();
    // Section 3.1: the robot at a 4 s period.
    assert!((p.period_s() - 4.0).abs() < 1e-12);
}

//! The inverse kinematics keeps joint trajectories continuous. The fly's front CTr on the ball used
//! to change branch between two slices (LF 73 -> 74 by 0.47 rad, RF 23 -> 24 by 0.40 rad: 190 rad/s
//! at the 2.5 ms slice time); now no joint of any leg steps more than its speed limit allows in
//! one slice (servo: no-load speed x dt; the fly: one turn per swing, 2 pi / 0.1 s x 2.5 ms =
//! 0.157 rad), or the plan names the step as an IK gap.

use planner::gait::StepParams;
use planner::kinematics::LegChain;
use planner::model::builtin;
use planner::plan::continuity::speed_limit;
use planner::plan::feasibility::jumps;

fn plan(model: &str, terrain: &str) -> planner::plan::Plan {
    let m = builtin(model).unwrap();
    let mut p = StepParams::table1(model);
    p.terrain = planner::terrain::Ground::parse(terrain).unwrap();
    planner::plan::plan(&m, &p).unwrap()
}

/// Every step over its bound that the plan does not name, as (joint, slice, step, bound).
fn unexplained_steps(p: &planner::plan::Plan) -> Vec<(String, usize, f64, f64)> {
    let n = p.slices();
    let mut out = Vec::new();
    for (j, joint) in p.model.joints.iter().enumerate() {
        let bound = speed_limit(&p.model, j, p.params.swing_s) * p.dt;
        for s in 0..n {
            let step = (p.q[(s + 1) % n][j] - p.q[s][j]).abs();
            let named = p
                .ik_gaps
                .iter()
                .any(|g| g.joint == joint.name && (g.first..=g.last).contains(&s));
            if step > bound && !named {
                out.push((joint.name.clone(), s, step, bound));
            }
        }
    }
    out
}

#[test]
fn the_flys_front_legs_on_the_ball_no_longer_jump() {
    let p = plan("scale-drosophila", "ball");
    // The bound: 2 pi / T_sw x dt, T_sw = 0.1 s, dt = 0.25 s / 100.
    let ctr = p
        .model
        .joints
        .iter()
        .position(|j| j.name == "LF_CTr")
        .unwrap();
    let bound = speed_limit(&p.model, ctr, 0.1) * p.dt;
    assert!((bound - std::f64::consts::TAU / 0.1 * 0.0025).abs() < 1e-12);
    let bad = unexplained_steps(&p);
    assert!(bad.is_empty(), "{bad:?}");
    // The old branch changes are gone, and the feasibility check's jump heuristic finds none.
    for name in ["LF_CTr", "RF_CTr"] {
        let j = p.model.joints.iter().position(|x| x.name == name).unwrap();
        let biggest = (0..p.slices())
            .map(|s| (p.q[(s + 1) % p.slices()][j] - p.q[s][j]).abs())
            .fold(0.0, f64::max);
        assert!(biggest <= bound, "{name}: largest step {biggest:.4} rad");
        assert!(jumps(&p.q, j).is_empty(), "{name}: {:?}", jumps(&p.q, j));
    }
    assert!(p.ik_gaps.is_empty(), "{:?}", p.ik_gaps);
    // Still a solution: every foot on its target (the IK's 1e-9 of the leg length), every joint
    // within its limits.
    for (li, leg) in p.legs.iter().enumerate() {
        let chain = LegChain::new(&p.model, *leg).unwrap();
        for s in 0..p.slices() {
            let qa: Vec<f64> = chain.actuated.iter().map(|&j| p.q[s][j]).collect();
            let miss = (chain.foot_position(&qa) - p.feet[s][li]).norm();
            assert!(miss < 1e-8 * chain.length, "{leg:?} slice {s}: {miss:e} m");
            for (k, &j) in chain.actuated.iter().enumerate() {
                let (lo, hi) = chain.limits(k);
                assert!(
                    lo - 1e-12 <= qa[k] && qa[k] <= hi + 1e-12,
                    "{}",
                    p.model.joints[j].name
                );
            }
        }
    }
}

#[test]
fn a_footpath_faster_than_the_servos_is_named_where_no_continuous_solution_exists() {
    // Drosophibot II on the ball at the original solver's 0.5 s swing: the front FTi must turn
    // about 8.4 rad/s (0.105 rad per 12.5 ms slice) against the MX-28's 5.76 rad/s (0.072 rad).
    let p = plan("drosophibot2", "ball");
    let dt = 1.25 / 100.0;
    assert!((p.dt - dt).abs() < 1e-15);
    let bad = unexplained_steps(&p);
    assert!(bad.is_empty(), "{bad:?}");
    for leg in ["LF", "RF"] {
        let g = p
            .ik_gaps
            .iter()
            .find(|g| g.joint == format!("{leg}_FTi"))
            .unwrap_or_else(|| panic!("{leg}_FTi not named: {:?}", p.ik_gaps));
        assert!((g.bound - 55.0 * std::f64::consts::TAU / 60.0 * dt).abs() < 1e-6);
        assert!(g.step > 1.4 * g.bound && !g.avoidable(), "{g}");
        assert!(
            g.to_string()
                .contains("no continuous solution within the joint limits")
        );
    }
}

#[test]
fn the_default_walk_has_no_gaps() {
    let m = builtin("drosophibot2").unwrap();
    for terrain in ["flat", "ball"] {
        let mut p = StepParams::preset("servo-safe", "drosophibot2").unwrap();
        p.terrain = planner::terrain::Ground::parse(terrain).unwrap();
        let p = planner::plan::plan(&m, &p).unwrap();
        assert!(p.ik_gaps.is_empty(), "{terrain}: {:?}", p.ik_gaps);
        assert!(unexplained_steps(&p).is_empty());
    }
}

//! The refinement after Levenberg-Marquardt (`lab::identify::refine`): on a short sus-TrF1
//! recording of the stand-in, Levenberg-Marquardt ends with LF_TrF1's stall torque 18 % high
//! (in the valley of equal stiffness, the damping, friction and deadband adapted to it), and
//! Nelder-Mead on the joint's own cost from there brings it within 10 % of the truth.

use super::identify::stand_in_recording;
use lab::identify::fit::MotionFit;
use lab::identify::refine::refine;
use lab::identify::stand_in;
use planner::model::ServoParamsEntry;

/// The refinement's replays in this test.
const BUDGET: usize = 150;

#[test]
fn the_refinement_brings_the_stall_torque_back_from_where_levenberg_marquardt_stops() {
    let default = planner::model::builtin("drosophibot2").unwrap();
    let truth = stand_in::stand_in_model(&default);
    let rec = stand_in_recording(&default, &[("LF_TrF1", "TrF1")]);
    let recs = std::slice::from_ref(&rec);
    let j = default.joint_index("LF_TrF1").unwrap();
    // Where Levenberg-Marquardt ends on this recording from `stand_in::start_model` (measured:
    // `identify` with `refine_replays_per_joint: 0`, 117 replays), its fit's fields rounded;
    // starting there spares the test that fit's 25 s.
    let mut lm = stand_in::start_model(&default);
    let mut e = lm
        .servo_dynamics
        .of_joint("LF_TrF1")
        .copied()
        .unwrap_or_default();
    e = ServoParamsEntry {
        p_gain_divisor: Some(186.2),
        stall_torque_nm: Some(2.657),
        damping_nm_s_per_rad: Some(0.0268),
        friction_nm: Some(0.0278),
        armature_kg_m2: Some(0.00449),
        deadband_rad: Some(0.00332),
        backlash_rad: Some(0.00465),
        no_load_speed_rad_s: Some(2.657 / lm.servo_params(j).unwrap().back_emf_nm_s_per_rad()),
        ..e
    };
    lm.servo_dynamics.set_joint("LF_TrF1", e);
    let truth_p = truth.servo_params(j).unwrap();
    let off = |p: &planner::model::ServoParams| {
        (p.stall_torque_nm - truth_p.stall_torque_nm).abs() / truth_p.stall_torque_nm
    };
    assert!(off(&lm.servo_params(j).unwrap()) > 0.10);

    let fit = MotionFit::new(&lm, recs, vec![j], usize::MAX);
    // 150 replays: measured to reach the truth's neighbourhood here (90 ends at 2.49 N m, 11 %
    // high: the test then fails).
    let (x, done) = refine(&fit, fit.x(), BUDGET).unwrap();
    let refined = fit.model_at(&x);
    let p = refined.servo_params(j).unwrap();
    assert!(
        done[0].kept && done[0].cost_after < done[0].cost_before,
        "{done:?}"
    );
    assert!(done[0].replays <= BUDGET);
    for (what, f, t) in [
        ("stall torque", p.stall_torque_nm, truth_p.stall_torque_nm),
        ("P gain divisor", p.p_gain_divisor, truth_p.p_gain_divisor),
    ] {
        assert!(
            (f - t).abs() <= 0.10 * t,
            "{what}: refined {f}, truth {t} (more than 10 % off); {done:?}"
        );
    }
}

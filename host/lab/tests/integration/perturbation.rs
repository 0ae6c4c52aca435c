//! The perturbation platform on the physics robot: the lab's rise under one foot at a chosen step
//! raises that leg's load in that step above every unperturbed step's, the robot walks on, and a
//! step beyond the run or a leg that is not a leg is refused before anything moves.

use lab::perturbation::{lab_rise, walk_perturbed};
use planner::model::Leg;

fn tripod_table() -> Vec<u8> {
    lab::walk::tripod_table().unwrap()
}

#[test]
fn a_rising_platform_raises_the_leg_load_in_its_step_and_the_robot_walks_on() {
    let table = tripod_table();
    // The lab's platform (rest 2020, rise 2330, two cycles up) under RF in step 3 of 5, on
    // servo ID 23 (the built-in robot's joints have 1-22), set up on the board.
    let w = walk_perturbed(
        &table,
        &planner::terrain::Ground::Flat,
        lab_rise(Leg::RF, 3),
        5,
    )
    .unwrap();
    for s in &w.steps {
        eprintln!(
            "step {}: peak {:.2} N, mean {:.2} N",
            s.step, s.peak_n, s.mean_n
        );
    }
    eprintln!("platform top up to {:.2} mm", w.platform_peak_m * 1e3);
    assert_eq!(w.perturb.setup.servo_id, 23);
    let hit = w.perturbed().unwrap().peak_n;
    let calm = w.unperturbed_peak_n();
    // Bound: 15 % above the larger peak of the neighbouring steps. Their peaks differ from each
    // other by 0.3 % (measured 9.28 and 9.25 N for steps 2 and 4), so 15 % is fifty times the
    // step-to-step spread; measured: 11.79 N, +27 %, with the top 0.61 mm up (the goal reaches
    // the slide in the Sync Write of the step's first cycle, so the body follows one cycle later).
    assert!(
        hit > 1.15 * calm,
        "perturbed step {hit} N, unperturbed at most {calm} N"
    );
    // The platform moved (the lab's profile velocity gives it about 0.7 mm in its two
    // cycles) and is back: the robot walks on, no fall, no sag beyond 1 cm, and the step after
    // the perturbation loads the leg as the one before did (within 5 %).
    assert!(w.platform_peak_m > 1e-4, "{}", w.platform_peak_m);
    assert_eq!(w.figures.verdict(0.01), None);
    let (before, after) = (w.steps[2].peak_n, w.steps[4].peak_n);
    assert!(
        (after - before).abs() < 0.05 * before,
        "{before} N, then {after} N"
    );
}

#[test]
fn a_step_beyond_the_run_and_a_leg_that_is_not_a_leg_are_refused() {
    let e = walk_perturbed(
        &[],
        &planner::terrain::Ground::Flat,
        lab_rise(Leg::LF, 4),
        4,
    )
    .unwrap_err()
    .to_string();
    assert_eq!(
        e,
        "perturbation step 4 is beyond the run's 4 steps (steps count from 0: at most 3)"
    );
    assert_eq!(
        board::platform::leg_named("LX").unwrap_err().to_string(),
        "perturbation leg `LX` is not a leg (legs: LF, LM, LH, RF, RM, RH)"
    );
    assert_eq!(board::platform::leg_named("RM"), Ok(Leg::RM));
}

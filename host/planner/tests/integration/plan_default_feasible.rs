//! The default walk (`servo-safe`: table 1 at a 1.0 s swing) is one Drosophibot II's servos can
//! follow, with headroom: on flat ground and on the ball every joint stays at or below 75 % of its
//! servo's datasheet no-load speed (MX-28 55 rev/min, MX-64 63 rev/min) and at least 0.5 N m under
//! the torque-speed line, while the original solver's 0.5 s swing (`table1`) is over the front
//! FTi's no-load speed. Speeds scale as 1 / swing for the same footpath, so 0.5 s -> 1.0 s halves
//! them: the 6.1 rad/s (flat) and 8.4 rad/s (ball) of the front FTi at 0.5 s become about 3.1 and
//! 4.2 rad/s, 53 % and 73 % of 5.76 rad/s.

use planner::dynamics::output::torque_rows;
use planner::dynamics::{DynamicsOptions, plan_inputs, solve_cycle};
use planner::gait::{SERVO_SAFE_SWING_S, StepParams};
use planner::model::builtin;
use planner::plan::feasibility::{Feasibility, Violation, check};

fn feasibility(preset: &str, terrain: &str) -> Feasibility {
    let model = builtin("drosophibot2").unwrap();
    let mut p = StepParams::preset(preset, &model.name).unwrap();
    p.terrain = planner::terrain::Ground::parse(terrain).unwrap();
    let plan = planner::plan::plan(&model, &p).unwrap();
    let cycle = solve_cycle(
        &plan.model,
        &plan_inputs(&plan),
        &DynamicsOptions::default(),
    )
    .unwrap();
    check(&plan.model, &plan.q, Some(&torque_rows(&cycle)), plan.dt)
}

#[test]
fn the_default_walk_keeps_a_quarter_of_every_servos_speed_in_reserve() {
    assert_eq!(SERVO_SAFE_SWING_S, 1.0);
    let model = builtin("drosophibot2").unwrap();
    let p = StepParams::preset("servo-safe", &model.name).unwrap();
    // Table 1's range is 0.4 to 1.6 s; the period is T_sw / (1 - 0.6) = 2.5 s.
    assert!((p.period_s() - 2.5).abs() < 1e-12);
    for terrain in ["flat", "ball"] {
        let f = feasibility("servo-safe", terrain);
        assert!(f.is_feasible(), "{terrain}: {:?}", f.violations);
        for j in &f.joints {
            let l = j.limits.unwrap();
            let share = j.speed.value / l.no_load_speed;
            assert!(
                share <= 0.75,
                "{terrain}: {} at {:.2} rad/s is {:.0} % of its {} no-load speed",
                j.joint,
                j.speed.value,
                100.0 * share,
                l.name
            );
            let margin = j.torque_speed_margin.unwrap().value;
            assert!(
                margin >= 0.5,
                "{terrain}: {} only {margin:.3} N m under the torque-speed line",
                j.joint
            );
        }
    }
}

#[test]
fn the_original_solvers_half_second_swing_is_too_fast_for_the_front_tibiae() {
    let f = feasibility("table1", "ball");
    for leg in ["LF", "RF"] {
        assert!(
            f.violations.iter().any(|v| matches!(v,
                Violation::Speed { joint, speed, limit, .. }
                    if *joint == format!("{leg}_FTi") && *speed > 1.4 * *limit)),
            "{leg}_FTi: {:?}",
            f.violations
        );
    }
}

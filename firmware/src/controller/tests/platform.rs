//! The perturbation platform on the controller: its goal in every goal Sync Write, `rise` at the
//! first cycle of the chosen step and `rest` exactly `hold_cycles` cycles later (counted from the
//! period and the cycle rate, 1 s at 100 Hz = 100 cycles a step), its torque switched with the
//! joints', and the refusals before anything moves (a joint's ID, a servo that does not answer, a
//! step beyond the run), with the words the host shows.

use protocol::{PlatformError, PlatformMove, PlatformSetup, PlatformState};

use super::*;
use crate::link::convert::command_error;

/// The lab's platform on ID 23 (the synthetic gait's joints are IDs 1 ..= 22), rising at `step`.
fn setup(step: u32) -> PlatformSetup {
    PlatformSetup {
        servo_id: 23,
        ..PlatformSetup::lab(PlatformMove::Rise, step)
    }
}

/// A booted rig (Idle) with the platform set up and checked.
fn rig_with_platform(step: u32) -> Rig {
    let mut r = Rig::idle();
    r.c.set_platform(setup(step)).unwrap();
    assert!(matches!(r.cycle(), BusAction::PlatformCheck { id: 23, .. }));
    r
}

#[test]
fn the_platform_rises_at_the_first_cycle_of_its_step_and_rests_two_cycles_later() {
    let mut r = rig_with_platform(1);
    // The servo stood at 2047 when checked, and was sent to rest (2020).
    assert_eq!(
        r.c.platform().unwrap().state,
        PlatformState::Ready { present: 2047 }
    );
    r.play(Some(3));
    // The platform's goal in each cycle planned while walking (the ramp's last cycle, which
    // arrives at slice 0, is not one), up to standing after step 2.
    let mut walk = vec![];
    for _ in 0..600 {
        let before = r.servos.platform_goals.len();
        let walking = r.c.state() == State::Walking;
        r.cycle();
        if r.servos.platform_goals.len() > before && walking {
            walk.push(r.servos.platform_goals.last().unwrap().unwrap());
        }
        if r.c.state() == State::Standing {
            break;
        }
    }
    assert_eq!(r.c.state(), State::Standing);
    // Every goal cycle carried the platform's goal, the ramp's and standing's included.
    assert!(r.servos.platform_goals.iter().all(Option::is_some));
    // Walking cycle k plays the gait at (k + 1) x 10 ms after the ramp arrived at slice 0: step 1
    // starts at 1 s, in cycle 99; three steps are 300 cycles.
    assert_eq!(walk.len(), 300);
    let rises: Vec<usize> = (0..walk.len()).filter(|&k| walk[k] == 2330).collect();
    assert_eq!(
        rises,
        [99, 100],
        "rise cycles of {} walking cycles",
        walk.len()
    );
    assert!(walk.iter().all(|&g| g == 2330 || g == 2020));
    // The servo followed: it is back at rest.
    assert_eq!(r.servos.platform_pos, 2020);
}

#[test]
fn telemetry_carries_the_platform_servo_goal_and_position() {
    let mut r = rig_with_platform(0);
    while r.c.pop_telemetry().is_some() {}
    r.play(Some(1));
    let mut lines = vec![];
    for _ in 0..300 {
        r.cycle();
        while let Some(rec) = r.c.pop_telemetry() {
            if rec.state == State::Walking {
                lines.push(rec.platform.expect("a platform line while walking"));
            }
        }
        if r.c.state() == State::Standing {
            break;
        }
    }
    // Step 0 starts with the cycle that arrives at its slice 0 (the ramp's last, recorded as
    // walking): rise in it and the next, read back as reached.
    assert_eq!(lines[0].goal, 2330);
    assert_eq!(lines[1].goal, 2330);
    assert_eq!(lines[2].goal, 2020);
    assert_eq!(
        (lines[0].id, lines[0].present, lines[0].flags),
        (23, 2330, 0)
    );
    assert_eq!(lines[2].present, 2020);
}

#[test]
fn the_platform_servo_switches_torque_with_the_joints() {
    let mut r = rig_with_platform(0);
    r.play(Some(1));
    assert_eq!(r.cycle(), BusAction::TorqueOn);
    assert!(r.servos.platform_torque);
    r.c.emergency_stop();
    assert_eq!(r.cycle(), BusAction::TorqueOff);
    assert!(!r.servos.platform_torque);
}

#[test]
fn a_platform_on_a_joints_id_or_with_nonsense_is_refused() {
    let mut r = Rig::idle();
    // The lab's ID 22 is joint 21's in the synthetic gait.
    let lab = PlatformSetup::lab(PlatformMove::Rise, 0);
    let e = r.c.set_platform(lab).unwrap_err();
    assert_eq!(
        e,
        CommandError::Platform(PlatformError::JointId {
            servo_id: 22,
            joint: 21
        })
    );
    assert_eq!(
        command_error(e).to_string(),
        "perturbation platform: platform servo ID 22 is the ID of joint 21: the platform needs a \
         servo of its own"
    );
    let zero = PlatformSetup {
        hold_cycles: 0,
        ..setup(0)
    };
    assert_eq!(
        r.c.set_platform(zero),
        Err(CommandError::Platform(PlatformError::ZeroHold))
    );
    assert_eq!(r.c.platform(), None);
}

#[test]
fn a_step_beyond_the_run_is_refused_when_it_starts() {
    let mut r = rig_with_platform(2);
    let e = r.try_play(Some(2)).unwrap_err();
    assert_eq!(
        command_error(e).to_string(),
        "perturbation platform: perturbation step 2 is beyond the run's 2 steps (steps count \
         from 0, so the last is 1)"
    );
    assert_eq!(r.c.state(), State::Idle);
    // Nothing moved: the next cycle writes no goals and torque stays off.
    assert!(matches!(
        r.cycle(),
        BusAction::ReadOnly | BusAction::TorqueOff
    ));
    assert!(!r.servos.torque);
    r.play(Some(3));
    assert_eq!(r.c.state(), State::Ramping);
}

#[test]
fn a_platform_servo_that_does_not_answer_is_named_before_anything_moves() {
    let mut r = Rig::idle();
    r.servos.platform_answers = false;
    r.c.set_platform(setup(0)).unwrap();
    // Before the check: the board says it is checking.
    let early = r.try_play(Some(1));
    assert_eq!(
        early,
        Err(CommandError::Platform(PlatformError::Checking {
            servo_id: 23
        }))
    );
    r.cycle();
    assert_eq!(r.c.platform().unwrap().state, PlatformState::NotAnswering);
    let e = r.try_play(Some(1)).unwrap_err();
    assert_eq!(
        command_error(e).to_string(),
        "perturbation platform: platform servo ID 23 does not answer (ping, profile velocity or \
         position read failed): check its cable and ID"
    );
    assert_eq!(r.c.state(), State::Idle);
    assert!(!r.servos.torque);
    // Cleared, the run starts without it.
    r.c.clear_platform().unwrap();
    r.play(Some(1));
    assert_eq!(r.c.state(), State::Ramping);
}

//! Gait switching on the controller: a queued gait takes over at the step boundary without a
//! stand, with goals continuous across the switch (hand-computed from both tables' boundary
//! slices), and the refusals of `protocol::switch` come back when the gait is queued.

use std::f64::consts::PI;

use protocol::SwitchError;
use protocol::gait::GaitTableBuilder;

use super::*;
use crate::testkit::gait::{stored_angle, stored_torque};

/// The synthetic gait plus `extra(s)` rad on every angle and `extra(s) / 2` N m on every torque,
/// `extra(s) = amp sin(2 pi s / slices) + offset`, with stance `stance(s)`: with `offset` 0 it
/// has the synthetic gait's slice 0, so it may follow it.
pub(super) fn variant(
    g: &SyntheticGait,
    name: &str,
    amp: f64,
    offset: f64,
    stance: impl Fn(usize) -> u8,
) -> Vec<u8> {
    let extra = |s: usize| amp * (2.0 * PI * s as f64 / g.slices as f64).sin() + offset;
    let mut b = GaitTableBuilder::new(name, g.period_s, 0.5, g.joints.clone());
    for s in 0..g.slices {
        let angles: Vec<f64> = (0..JOINTS).map(|j| g.angle(s, j) + extra(s)).collect();
        let torques: Vec<f64> = (0..JOINTS)
            .map(|j| g.torque(s, j) + extra(s) / 2.0)
            .collect();
        b.slice(stance(s), &angles, &torques);
    }
    b.build().unwrap()
}

/// The synthetic gait's tripod (LF LH RM, then the others).
pub(super) fn tripod(s: usize) -> u8 {
    if s < 50 { 0b010_101 } else { 0b101_010 }
}

/// Expected goal of the variant (amp 0.05, offset 0) at slice position `pos`, f64, from its own
/// rounded samples (the testkit's formula, the variant's extra added before rounding).
fn turn_goal(g: &SyntheticGait, pos: f64, j: usize) -> f64 {
    let extra = |s: usize| 0.05 * (2.0 * PI * s as f64 / 100.0).sin();
    g.goal_of(
        pos,
        j,
        STIFFNESS,
        |s| stored_angle(g.angle(s, j) + extra(s)),
        |s| stored_torque(g.torque(s, j) + extra(s) / 2.0),
    )
}

/// One bus cycle at 100 Hz is 0.01 s: an MX-28 at no load (55 rev/min = 5.7596 rad/s) turns
/// 0.057596 rad = 37.5 ticks in it; `protocol::switch::jump_bound` says 575e-4 rad.
pub(super) const BOUND_TICKS: f64 = 0.0575 * 4096.0 / (2.0 * PI);

#[test]
fn a_gait_queued_mid_step_takes_over_at_the_boundary_with_continuous_goals() {
    let mut r = Rig::idle();
    let turn = variant(&r.gait, "turn", 0.05, 0.0, tripod);
    upload(&mut r.c, 1, &turn);
    r.play(None);
    r.until(2000, State::Walking);
    for _ in 0..30 {
        r.cycle();
    }
    // Mid-swing (slice 30 of 100): the command waits for the boundary.
    r.c.queue_gait(forward(1, Some(1))).unwrap();
    assert_eq!(r.c.queued_slots().collect::<Vec<_>>(), [1]);
    let mut last: Vec<i32> = r.servos.pos[..JOINTS].to_vec();
    let mut n = 0;
    while r.c.selected_slot() == Some(0) {
        last = r.servos.pos[..JOINTS].to_vec();
        r.cycle();
        n += 1;
        assert_eq!(
            r.c.state(),
            State::Walking,
            "never stands between the gaits"
        );
    }
    // 30 cycles of the step were played: the switch is the 70th cycle, the step boundary.
    assert_eq!(n, 70);
    // Before: the synthetic gait at slice 99; after: the turn at its slice 0, which is the
    // synthetic gait's slice 0 (the turn's extra is sin(0) = 0 there).
    for (j, &l) in last.iter().enumerate() {
        let before = r.gait.goal(99.0, j, STIFFNESS);
        let after = turn_goal(&r.gait, 0.0, j);
        assert!((l as f64 - before).abs() <= 1.0, "joint {j} before");
        assert!(
            (r.servos.pos[j] as f64 - after).abs() <= 1.0,
            "joint {j} after"
        );
        let step = (r.servos.pos[j] - l).abs() as f64;
        assert!(
            (step - (after - before).abs()).abs() <= 2.0 && step <= BOUND_TICKS,
            "joint {j}: {step} ticks across the switch, bound {BOUND_TICKS:.1}"
        );
    }
    // The turn plays its own angles and torque bias from its first slice on.
    for k in 1..100 {
        r.cycle();
        if r.c.state() != State::Walking {
            break;
        }
        for j in 0..JOINTS {
            let want = turn_goal(&r.gait, k as f64, j);
            assert!(
                (r.servos.pos[j] as f64 - want).abs() <= 1.0,
                "turn cycle {k} joint {j}: {} vs {want:.2}",
                r.servos.pos[j]
            );
        }
    }
    // One step of the turn, then standing at its boundary; the step count ran on: 1 + 1.
    r.until(10, State::Standing);
    assert_eq!(r.c.playback().unwrap().0, 2);
}

#[test]
fn a_counted_gait_plays_its_steps_before_the_queued_one_and_the_queue_plays_in_order() {
    let mut r = Rig::idle();
    let turn = variant(&r.gait, "turn", 0.05, 0.0, tripod);
    upload(&mut r.c, 1, &turn);
    r.play(Some(2));
    r.c.queue_gait(forward(1, Some(1))).unwrap();
    r.c.queue_gait(PlayParams {
        direction: Direction::Backward,
        ..forward(0, Some(1))
    })
    .unwrap();
    r.until(2000, State::Walking);
    let mut slots = vec![];
    let mut cycles = 0;
    while r.c.state() == State::Walking {
        r.cycle();
        cycles += 1;
        let s = r.c.selected_slot().unwrap();
        if slots.last() != Some(&s) {
            slots.push(s);
        }
    }
    // 2 + 1 + 1 steps of 100 cycles, never standing in between; slot 0, the turn, slot 0 back.
    assert_eq!(cycles, 400);
    assert_eq!(slots, [0, 1, 0]);
    assert_eq!(r.c.play_clock().unwrap().direction(), Direction::Backward);
    assert_eq!(r.c.state(), State::Standing);
    assert_eq!(r.c.playback().unwrap().0, 4);
}

#[test]
fn a_gait_that_cannot_follow_is_refused_when_queued_with_its_reason() {
    let mut r = Rig::idle();
    // 0.1 rad and 0.05 N m more everywhere. Joint 0 (an MX-28) at slice 0: angle 0 -> 1000e-4 rad,
    // torque 300 -> 350 mN m, bias 300 x 1e4 / 8400 = 357 -> 350 x 1e4 / 8400 = 416 (1e-4 rad,
    // truncated): a jump of 1000 + 59 = 1059e-4 rad, over the bound 575e-4 at 100 Hz.
    upload(&mut r.c, 1, &variant(&r.gait, "high", 0.0, 0.1, tripod));
    // Legs LF LH RM in stance at both ends of the step: the others are in the air there, where
    // the synthetic gait has all six on the ground (its tripods change at the boundary).
    let odd = |s: usize| {
        if (25..75).contains(&s) {
            0b101_010
        } else {
            0b010_101
        }
    };
    upload(&mut r.c, 2, &variant(&r.gait, "odd", 0.0, 0.0, odd));
    // Not walking: nothing to follow.
    assert!(matches!(
        r.c.queue_gait(forward(0, None)),
        Err(CommandError::WrongState(_))
    ));
    r.play(None);
    assert_eq!(
        r.c.queue_gait(forward(1, None)),
        Err(CommandError::Switch(SwitchError::JointJump {
            joint: 0,
            jump: 1059,
            bound: 575
        }))
    );
    assert_eq!(
        r.c.queue_gait(forward(2, None)),
        Err(CommandError::Switch(SwitchError::Stance {
            playing: 0b111_111,
            queued: 0b010_101
        }))
    );
    assert_eq!(
        r.c.queue_gait(forward(3, None)),
        Err(CommandError::SlotEmpty { slot: 3 })
    );
    for _ in 0..QUEUE_LEN {
        r.c.queue_gait(forward(0, None)).unwrap();
    }
    assert_eq!(
        r.c.queue_gait(forward(0, None)),
        Err(CommandError::Switch(SwitchError::QueueFull {
            capacity: QUEUE_LEN as u8
        }))
    );
    r.c.clear_queue().unwrap();
    assert_eq!(r.c.queued_slots().count(), 0);
}

#[test]
fn stop_and_a_lost_host_drop_the_queue_and_end_the_step() {
    let mut r = Rig::idle_with(host_timeout(50));
    // A counted run with an endless gait queued is a commanded walk the host-loss rule covers.
    r.play(Some(5));
    r.c.queue_gait(forward(0, None)).unwrap();
    r.until(2000, State::Walking);
    r.c.host_contact();
    let n = r.until(60, State::Stopping);
    assert_eq!(n, 51);
    assert_eq!(r.c.queued_slots().count(), 0);
    assert!(matches!(
        r.c.queue_gait(forward(0, None)),
        Err(CommandError::WrongState(_))
    ));
    r.until(200, State::Standing);
    assert_eq!(r.c.play_clock().unwrap().phase_us(), 0, "never mid-step");
    assert_eq!(r.c.playback().unwrap().0, 1);
    // Stop while a gait waits: the step ends, the queued gait never plays.
    r.play(None);
    r.c.queue_gait(forward(0, Some(3))).unwrap();
    r.until(2000, State::Walking);
    r.c.host_contact();
    r.c.stop().unwrap();
    assert_eq!(r.c.queued_slots().count(), 0);
    r.until(200, State::Standing);
    assert_eq!(r.c.playback().unwrap().0, 1);
}

#[test]
fn a_lost_host_after_the_switch_stops_the_queued_gait_at_the_end_of_its_step() {
    let mut r = Rig::idle_with(host_timeout(150));
    upload(&mut r.c, 1, &variant(&r.gait, "turn", 0.05, 0.0, tripod));
    // One counted step, then the turn without end: once it plays, only the host keeps it going.
    r.play(Some(1));
    r.c.queue_gait(forward(1, None)).unwrap();
    while r.c.selected_slot() != Some(1) {
        r.c.host_contact();
        r.cycle();
    }
    assert_eq!(r.c.state(), State::Walking);
    // 30 cycles into the turn's first step (slice 30, mid-swing of LM RF RH), the host falls silent.
    for _ in 0..30 {
        r.c.host_contact();
        r.cycle();
    }
    assert_eq!(r.c.playback(), Some((1, 30)));
    // The last contact came before the last cycle above, so that cycle was the first silent one;
    // the 151st is over the limit of 150, 150 cycles on: slice 30 + 150 = 180, slice 80 of the
    // turn's second step. It ends that step (20 more cycles) and stands, on the turn's slot.
    let n = r.until(200, State::Stopping);
    assert_eq!(n, 150);
    assert_eq!(r.c.playback(), Some((2, 80)));
    let n = r.until(100, State::Standing);
    assert_eq!(n, 20);
    assert_eq!(r.c.play_clock().unwrap().phase_us(), 0, "never mid-step");
    assert_eq!(r.c.playback().unwrap().0, 3);
    assert_eq!(r.c.selected_slot(), Some(1));
    assert_eq!(r.c.counters().host_lost, 1);
}

#[test]
fn a_gait_queued_during_the_ramp_takes_over_after_the_first_step() {
    let mut r = Rig::idle();
    upload(&mut r.c, 1, &variant(&r.gait, "turn", 0.05, 0.0, tripod));
    r.play(None);
    assert_eq!(r.c.state(), State::Ramping);
    r.c.queue_gait(forward(1, Some(1))).unwrap();
    r.until(2000, State::Walking);
    // The ramp ends on slice 0; a whole step of the first gait (100 cycles of 10 ms) plays before
    // the queued one takes over at its boundary.
    let n = r.cycles_until(200, |r| r.c.selected_slot() == Some(1));
    assert_eq!(n, 100);
    assert_eq!(r.c.state(), State::Walking);
    assert_eq!(r.c.playback(), Some((1, 0)));
}

#[test]
fn clearing_the_queue_mid_swing_keeps_the_gait_playing() {
    let mut r = Rig::idle();
    upload(&mut r.c, 1, &variant(&r.gait, "turn", 0.05, 0.0, tripod));
    r.play(None);
    r.until(2000, State::Walking);
    for _ in 0..30 {
        r.cycle();
    }
    r.c.queue_gait(forward(1, None)).unwrap();
    r.c.clear_queue().unwrap();
    // Three boundaries later slot 0 still plays, never standing.
    for _ in 0..300 {
        r.cycle();
        assert_eq!(r.c.state(), State::Walking);
        assert_eq!(r.c.selected_slot(), Some(0));
    }
    assert_eq!(r.c.playback(), Some((3, 30)));
}

//! Steering on the controller: the blend of a heading at every phase (hand-computed from the
//! family's rounded samples), a command mid-swing waiting for the boundary, the blend's rate limit
//! keeping every goal within the switch rule's bound, the host-loss rule, and the refusals of
//! `protocol::steer`.

use std::f64::consts::PI;

use protocol::gait::GaitTableBuilder;
use protocol::{SteerCommand, SteerError, SteerFamily};

use super::switch::{BOUND_TICKS, tripod, variant};
use super::*;
use crate::safety::{Event, Refused};
use crate::testkit::gait::{stored_angle, stored_torque};

const FAMILY: SteerFamily = SteerFamily {
    straight: 0,
    left: 1,
    right: 2,
    range_mrad: 300,
};

fn cmd(heading_mrad: i16) -> SteerCommand {
    SteerCommand {
        heading_mrad,
        speed_permille: 1000,
    }
}

/// A rig with the synthetic gait in slot 0 and side gaits `extra(s) = amp sin(2 pi s / 100) +
/// offset` in slots 1 (left) and 2 (right), the family set.
fn family_rig(config: Config, left: (f64, f64), right: (f64, f64)) -> Rig {
    let mut r = Rig::idle_with(config);
    let l = variant(&r.gait, "left", left.0, left.1, tripod);
    let rt = variant(&r.gait, "right", right.0, right.1, tripod);
    upload(&mut r.c, 1, &l);
    upload(&mut r.c, 2, &rt);
    r.c.set_steer_family(FAMILY).unwrap();
    r
}

/// Expected goal (ticks, before rounding) of the blend of the synthetic gait with the side gait
/// `(amp, offset)` at weight `w` (0..=1) at slice position `pos`: each table's samples rounded
/// as stored (1e-4 rad, 1 mN m), blended per slice, then interpolated between slices.
fn blend_goal(g: &SyntheticGait, side: (f64, f64), w: f64, pos: f64, j: usize) -> f64 {
    let extra = |s: usize| side.0 * (2.0 * PI * s as f64 / 100.0).sin() + side.1;
    let angle = |s: usize| {
        let a = stored_angle(g.angle(s, j));
        a + w * (stored_angle(g.angle(s, j) + extra(s)) - a)
    };
    let torque = |s: usize| {
        let t = stored_torque(g.torque(s, j));
        t + w * (stored_torque(g.torque(s, j) + extra(s) / 2.0) - t)
    };
    g.goal_of(pos, j, STIFFNESS, angle, torque)
}

/// The slice position the goals of the last cycle came from (100 slices over 1 s).
fn pos(r: &Rig) -> f64 {
    r.c.play_clock().unwrap().phase_us() as f64 / 10_000.0
}

fn assert_blend(r: &Rig, side: (f64, f64), w: f64, what: &str) {
    let p = pos(r);
    for j in 0..JOINTS {
        let want = blend_goal(&r.gait, side, w, p, j);
        let got = r.servos.pos[j] as f64;
        assert!(
            (got - want).abs() <= 1.0,
            "{what}: joint {j} at slice {p:.2}: {got} ticks, want {want:.2}"
        );
    }
}

#[test]
fn a_heading_plays_its_share_of_the_side_gait_and_a_new_one_waits_for_the_boundary() {
    let (left, right) = ((0.05, 0.0), (0.08, 0.0));
    let mut r = family_rig(Config::default(), left, right);
    // -100 of 300 mrad: a third of the right gait, -100 x 65536 / 300 = -21845 (truncated).
    r.c.steer(cmd(-100)).unwrap();
    assert_eq!(r.c.steer_blend(), Some((-21_845, -21_845)));
    r.until(2000, State::Walking);
    let w_right = 21_845.0 / 65_536.0;
    for _ in 0..30 {
        r.cycle();
        assert_blend(&r, right, w_right, "a third right");
    }
    // Mid-swing (slice 30): half left from the next boundary on (a change of 0.83 <= 1 side gait).
    r.c.steer(cmd(150)).unwrap();
    assert_eq!(r.c.steer_blend(), Some((-21_845, 32_768)));
    while pos(&r) >= 30.0 {
        r.cycle();
        if pos(&r) >= 30.0 {
            assert_blend(
                &r,
                right,
                w_right,
                "still a third right before the boundary",
            );
        }
    }
    assert_eq!(r.c.steer_blend(), Some((32_768, 32_768)));
    for _ in 0..100 {
        assert_blend(&r, left, 0.5, "half left after the boundary");
        r.cycle();
    }
    assert_eq!(r.c.state(), State::Walking);
}

#[test]
fn full_left_to_full_right_goes_through_straight_and_no_goal_jumps_beyond_the_switch_bound() {
    // Sides 0.04 rad and 0.02 N m off the straight gait everywhere: across a boundary a whole
    // side gait moves a goal by (0.04 + 0.02 / 8.4) x 4096 / 2 pi = 27.63 ticks, under the bound
    // (37.5 ticks at 100 Hz); left to right at once would be 55.3, over it.
    let one_side = (0.04 + 0.02 / STIFFNESS) * 4096.0 / (2.0 * PI);
    assert!(one_side < BOUND_TICKS && 2.0 * one_side > BOUND_TICKS);
    let (left, right) = ((0.0, 0.04), (0.0, -0.04));
    let mut r = family_rig(Config::default(), left, right);
    r.c.steer(cmd(300)).unwrap();
    r.until(2000, State::Walking);
    for _ in 0..40 {
        r.cycle();
    }
    assert_blend(&r, left, 1.0, "full left");
    r.c.steer(cmd(-300)).unwrap();
    let mut blends = vec![];
    let mut worst = 0.0f64;
    for _ in 0..260 {
        let (before, p0) = (r.servos.pos, pos(&r));
        r.cycle();
        let p1 = pos(&r);
        let b = r.c.steer_blend().unwrap().0;
        if blends.last() != Some(&b) {
            blends.push(b);
        }
        for (j, (&now, &was)) in r.servos.pos.iter().zip(&before).take(JOINTS).enumerate() {
            // The goal's move beyond the straight gait's own motion over this cycle.
            let own = r.gait.goal(p1, j, STIFFNESS) - r.gait.goal(p0, j, STIFFNESS);
            let extra = ((now - was) as f64 - own).abs();
            worst = worst.max(extra);
        }
    }
    assert_eq!(blends, [65_536, 0, -65_536], "one side gait per boundary");
    assert!(
        (worst - one_side).abs() <= 2.0 && worst <= BOUND_TICKS,
        "largest jump {worst:.2} ticks, one side gait {one_side:.2}, bound {BOUND_TICKS:.1}"
    );
    assert_blend(&r, right, 1.0, "full right");
}

#[test]
fn a_steered_walk_without_its_host_stops_at_the_end_of_the_step() {
    let mut r = family_rig(host_timeout(50), (0.05, 0.0), (0.05, 0.0));
    r.c.steer(cmd(200)).unwrap();
    r.until(2000, State::Walking);
    r.c.host_contact();
    let n = r.until(60, State::Stopping);
    assert_eq!(n, 51);
    // A command after the stop was promised is refused; the step ends on the blend, at slice 0.
    assert!(matches!(
        r.c.steer(cmd(0)),
        Err(CommandError::WrongState(Refused {
            state: State::Stopping,
            event: Event::Steer
        }))
    ));
    r.until(200, State::Standing);
    assert_eq!(r.c.play_clock().unwrap().phase_us(), 0, "never mid-step");
    assert_eq!(r.c.steer_blend(), None);
    assert_eq!(r.c.counters().host_lost, 1);
}

#[test]
fn gaits_that_cannot_be_blended_and_commands_out_of_range_are_refused_with_the_reason() {
    let mut r = Rig::idle();
    assert_eq!(
        r.c.steer(cmd(0)),
        Err(CommandError::Steer(SteerError::NoFamily))
    );
    let g = &r.gait;
    let ok = variant(g, "ok", 0.05, 0.0, tripod);
    let slow = SyntheticGait::new(100, 1.2).build_named("slow");
    let short = SyntheticGait::new(50, 1.0).build_named("short");
    // Legs swapped in slices 20..30 only: the same legs on the ground at the boundary.
    let odd = variant(g, "odd", 0.0, 0.0, |s| {
        if (20..30).contains(&s) {
            0b101_010
        } else {
            tripod(s)
        }
    });
    let mut stiff = GaitTableBuilder::new(
        "stiff",
        g.period_s,
        0.5,
        g.joints
            .iter()
            .enumerate()
            .map(|(j, s)| protocol::JointSpec {
                stiffness_nm_per_rad: if j == 4 { 9.0 } else { STIFFNESS },
                leg: None,
                ..s.clone()
            })
            .collect(),
    );
    for s in 0..100 {
        let a: Vec<f64> = (0..JOINTS).map(|j| g.angle(s, j)).collect();
        let t: Vec<f64> = (0..JOINTS).map(|j| g.torque(s, j)).collect();
        stiff.slice(tripod(s), &a, &t);
    }
    let stiff = stiff.build().unwrap();
    upload(&mut r.c, 1, &ok);
    let with = |left: u8| SteerFamily { left, ..FAMILY };
    for (table, want) in [
        (
            &slow,
            SteerError::Period {
                slot: 2,
                period_us: 1_200_000,
                straight_us: 1_000_000,
            },
        ),
        (
            &short,
            SteerError::Slices {
                slot: 2,
                slices: 50,
                straight: 100,
            },
        ),
        (
            &odd,
            SteerError::Phase {
                slot: 2,
                slice: 20,
                stance: 0b101_010,
                straight: 0b010_101,
            },
        ),
        (&stiff, SteerError::Stiffness { slot: 2, joint: 4 }),
    ] {
        upload(&mut r.c, 2, table);
        assert_eq!(
            r.c.set_steer_family(with(1)),
            Err(CommandError::Steer(want))
        );
    }
    // The switch rule's refusal, named with the slot: 0.1 rad off at slice 0 (see switch.rs).
    upload(&mut r.c, 2, &variant(g, "high", 0.0, 0.1, tripod));
    assert!(matches!(
        r.c.set_steer_family(with(1)),
        Err(CommandError::Steer(SteerError::Switch {
            slot: 2,
            error: protocol::SwitchError::JointJump { joint: 0, .. }
        }))
    ));
    upload(&mut r.c, 2, &ok);
    assert_eq!(
        r.c.set_steer_family(SteerFamily {
            range_mrad: 0,
            ..FAMILY
        }),
        Err(CommandError::Steer(SteerError::ZeroRange))
    );
    r.c.set_steer_family(FAMILY).unwrap();
    assert_eq!(
        r.c.steer(cmd(301)),
        Err(CommandError::Steer(SteerError::Heading {
            heading_mrad: 301,
            range_mrad: 300
        }))
    );
    assert_eq!(
        r.c.steer(SteerCommand {
            heading_mrad: 0,
            speed_permille: 50
        }),
        Err(CommandError::Steer(SteerError::Speed {
            speed_permille: 50
        }))
    );
    // While steering: no queued gaits, no new family; a plain walk takes no steer command.
    r.c.steer(cmd(0)).unwrap();
    assert_eq!(
        r.c.queue_gait(forward(1, None)),
        Err(CommandError::Steer(SteerError::Steering))
    );
    assert_eq!(
        r.c.set_steer_family(FAMILY),
        Err(CommandError::Steer(SteerError::Steering))
    );
    r.c.stop().unwrap();
    r.until(3000, State::Standing);
    r.play(None);
    assert!(matches!(
        r.c.steer(cmd(0)),
        Err(CommandError::WrongState(Refused {
            state: State::Ramping,
            event: Event::Steer
        }))
    ));
}

#[test]
fn speed_scales_the_period_from_the_next_boundary() {
    let mut r = family_rig(Config::default(), (0.05, 0.0), (0.05, 0.0));
    r.c.steer(SteerCommand {
        heading_mrad: 0,
        speed_permille: 2000,
    })
    .unwrap();
    r.until(2000, State::Walking);
    // Twice the planned speed: a 1 s step in 50 cycles of 10 ms.
    let start = r.c.playback().unwrap().0;
    let n = r.cycles_until(200, |r| r.c.playback().unwrap().0 == start + 1);
    assert!((49..=51).contains(&n), "{n} cycles per step");
    r.c.steer(SteerCommand {
        heading_mrad: 0,
        speed_permille: 500,
    })
    .unwrap();
    r.cycles_until(200, |r| r.c.playback().unwrap().0 == start + 2);
    let n = r.cycles_until(400, |r| r.c.playback().unwrap().0 == start + 3);
    assert_eq!(n, 200, "half speed: 2 s per step");
}

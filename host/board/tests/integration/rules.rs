//! The rules of `board::rules` on hand-worked cases: a table played faster than planned against the
//! servos' e-manual limits, a faster play of a table the host does not hold, a steered walk faster
//! than planned (every table of the family checked), and the stiffness the P gain register holds.
//!
//! The synthetic gait (firmware testkit) has angle 0.4 sin(2 pi s / N + 0.5 j) rad and torque
//! 0.3 cos(same) N m: by central differences its joint 0 (an MX-28) peaks at slice 0 at
//! 0.4 sin(2 pi / N) / dt rad/s, with its full 0.3 N m there, driving its motion.

use std::f64::consts::TAU;

use board::link::Board;
use board::robot::{VirtualRobot, VirtualTransport};
use board::rules::period::{check_play, check_scaled};
use board::rules::steer::check_steer;
use board::rules::stiffness::{StiffnessError, units};
use board::rules::{Overridden, Overrides, RuleError};
use firmware::testkit::{JOINTS, SyntheticGait};
use protocol::gait::GaitTableBuilder;
use protocol::{Direction, GaitTable, PlayCommand, Steps};

/// MX-28(2.0) at 12 V (e-manual): 55 rev/min no load, 2.5 N m stall.
const W0: f64 = 55.0 * TAU / 60.0;
const STALL: f64 = 2.5;
const CHECK: Overrides = Overrides {
    allow_infeasible: false,
};
const ALLOW: Overrides = Overrides {
    allow_infeasible: true,
};

fn names() -> Vec<String> {
    (0..22).map(|j| format!("J{j}")).collect()
}

/// Joint 0's peak speed at `scale` times the 1.0 s period of a 100-slice synthetic gait.
fn peak(scale: f64) -> f64 {
    0.4 * (TAU / 100.0).sin() / (scale / 100.0)
}

#[test]
fn a_faster_play_is_refused_where_the_hand_computed_speed_passes_a_limit() {
    let bytes = SyntheticGait::new(100, 1.0).build();
    let t = GaitTable::parse(&bytes).unwrap();
    // As planned and slower: nothing to check.
    assert!(check_scaled(&t, &names(), 1, 1.0, CHECK).unwrap().is_none());
    assert!(check_scaled(&t, &names(), 1, 2.0, CHECK).unwrap().is_none());
    // The torque-speed line 2.5 (1 - w / w0) N m gives the 0.3 N m up to w = 0.88 w0 = 5.068
    // rad/s: scale 2.5116 / 5.068 = 0.4955. At 0.50 joint 0 turns at 5.023 rad/s: followed.
    assert!(peak(0.50) < (1.0 - 0.3 / STALL) * W0 && peak(0.49) > (1.0 - 0.3 / STALL) * W0);
    assert!(
        check_scaled(&t, &names(), 1, 0.50, CHECK)
            .unwrap()
            .is_none()
    );
    // At 0.49 (5.126 rad/s) the servo gives 0.275 N m there, less than the 0.3 N m.
    let e = check_scaled(&t, &names(), 1, 0.49, CHECK).unwrap_err();
    let text = e.to_string();
    let line = text
        .lines()
        .find_map(|l| {
            l.trim()
                .strip_prefix("J0 at slice 0: |torque| 0.300 N m at ")
        })
        .unwrap_or_else(|| panic!("no line for J0 at slice 0: {text}"));
    let number = |s: &str| s.split(' ').next().unwrap().parse::<f64>().unwrap();
    let speed = number(line);
    let (_, rest) = line.split_once(", over the ").unwrap();
    let available = number(rest);
    // The table keeps angles to 1e-4 rad: a central difference over 2 dt = 0.0098 s is off the
    // sine's by at most 2e-4 / 0.0098 = 0.02 rad/s; the available torque is the line's at the
    // speed measured (printed to 0.01 rad/s and 0.001 N m).
    assert!(
        (speed - peak(0.49)).abs() < 0.021,
        "{speed} vs {}",
        peak(0.49)
    );
    assert!(
        (available - STALL * (1.0 - speed / W0)).abs() < 0.0035 && available < 0.3,
        "{text}"
    );
    assert!(
        rest.contains(" N m the servo gives at that speed"),
        "{text}"
    );
    // At 0.40 (6.279 rad/s) it is over the no-load speed itself.
    let e = check_scaled(&t, &names(), 1, 0.40, CHECK).unwrap_err();
    assert!(matches!(e, RuleError::TooFast { .. }));
    let text = e.to_string();
    assert!(
        text.starts_with("slot 1 (\"synthetic\"): at 0.400 s per step (0.400 times the planned 1.000 s) the servos cannot follow it:\n"),
        "{text}"
    );
    assert!(
        text.contains(&format!(
            "J0 at slice 0: {:.2} rad/s, over the servo's no-load speed {W0:.2} rad/s",
            peak(0.40)
        )),
        "{text}"
    );
    // The override lets it through with the same lines as a warning.
    let w = check_scaled(&t, &names(), 1, 0.40, ALLOW).unwrap().unwrap();
    assert!(
        w.to_string()
            .contains(&format!("J0 at slice 0: {:.2} rad/s", peak(0.40)))
    );
}

#[test]
fn a_faster_play_of_a_table_the_host_does_not_hold_is_refused_unless_overridden() {
    let mut b = Board::connect(VirtualTransport::new(VirtualRobot::new())).unwrap();
    let bytes = SyntheticGait::new(100, 1.0).build();
    let crc = GaitTable::parse(&bytes).unwrap().crc();
    gate::upload(&mut b, 1, &bytes).unwrap();
    let model = planner::model::builtin("drosophibot2").unwrap();
    let play = |scale: u16| PlayCommand {
        slot: 1,
        direction: Direction::Forward,
        period_scale: scale,
        steps: Steps::Count(1),
    };
    // At the planned period and slower the table is not needed.
    assert!(
        check_play(&mut b, play(1000), None, &model, CHECK)
            .unwrap()
            .warning()
            .is_none()
    );
    assert!(
        check_play(&mut b, play(1500), None, &model, CHECK)
            .unwrap()
            .warning()
            .is_none()
    );
    let e = check_play(&mut b, play(800), None, &model, CHECK).unwrap_err();
    assert!(
        e.to_string().contains(&format!(
            "this host does not hold its table (CRC {crc:#010x}"
        )),
        "{e}"
    );
    let w = check_play(&mut b, play(800), None, &model, ALLOW)
        .unwrap()
        .warning()
        .cloned()
        .unwrap();
    assert_eq!(
        w,
        Overridden::Unchecked {
            slot: 1,
            scale: 0.8,
            crc
        }
    );
    // Held: 0.8 is fine (joint 0 at 3.14 rad/s), 0.4 is not.
    assert!(
        check_play(&mut b, play(800), Some(&bytes), &model, CHECK)
            .unwrap()
            .warning()
            .is_none()
    );
    let e = check_play(&mut b, play(400), Some(&bytes), &model, CHECK).unwrap_err();
    assert!(matches!(e, RuleError::TooFast { .. }), "{e}");
    // A different table than the slot's is not the slot's.
    let other = SyntheticGait::new(100, 2.0).build();
    let e = check_play(&mut b, play(800), Some(&other), &model, CHECK).unwrap_err();
    assert!(matches!(e, RuleError::UnknownTable { .. }), "{e}");
}

/// The synthetic gait (100 slices, 1.0 s) with `amp sin(2 pi s / 100)` rad more on every angle,
/// named `name`: the same slice 0, phases and stiffness as the synthetic gait, so the board takes
/// the two as a steering family. Joint 0 then peaks at slice 0 at (0.4 + amp) sin(2 pi / 100) / dt.
fn turning(name: &str, amp: f64) -> Vec<u8> {
    let g = SyntheticGait::new(100, 1.0);
    let mut b = GaitTableBuilder::new(name, g.period_s, 0.5, g.joints.clone());
    for s in 0..g.slices {
        let extra = amp * (TAU * s as f64 / 100.0).sin();
        let a: Vec<f64> = (0..JOINTS).map(|j| g.angle(s, j) + extra).collect();
        let t: Vec<f64> = (0..JOINTS).map(|j| g.torque(s, j)).collect();
        b.slice(if s < 50 { 0b010_101 } else { 0b101_010 }, &a, &t);
    }
    b.build().unwrap()
}

#[test]
fn steering_faster_than_planned_checks_every_table_of_the_family() {
    let mut b = Board::connect(VirtualTransport::new(VirtualRobot::new())).unwrap();
    let model = planner::model::builtin("drosophibot2").unwrap();
    let straight = turning("straight", 0.0);
    let left = turning("left", 0.1);
    let right = turning("right", -0.1);
    for (slot, t) in [(0, &straight), (1, &left), (2, &right)] {
        gate::upload(&mut b, slot, t).unwrap();
    }
    let held = |slot: u8| {
        Ok([&straight, &left, &right]
            .get(usize::from(slot))
            .map(|t| t.to_vec()))
    };
    let none = |_: u8| Ok(None);
    // No family set from here: faster than planned cannot be checked.
    let e = check_steer(&mut b, 0.0, 2.0, &held, &model, CHECK).unwrap_err();
    assert!(matches!(e, RuleError::UnknownFamily { .. }), "{e}");
    assert!(
        e.to_string()
            .starts_with("steering at speed 2: faster than planned needs a check"),
        "{e}"
    );
    assert_eq!(
        check_steer(&mut b, 0.0, 2.0, &held, &model, ALLOW)
            .unwrap()
            .warning()
            .cloned(),
        Some(Overridden::SteerUnchecked { speed: 2.0 })
    );
    b.set_steer_family(0, 1, 2, 0.06).unwrap();
    // As planned and slower: nothing to check, nothing needed.
    assert!(
        check_steer(&mut b, 0.0, 1.0, &none, &model, CHECK)
            .unwrap()
            .warning()
            .is_none()
    );
    assert!(
        check_steer(&mut b, 0.0, 0.5, &none, &model, CHECK)
            .unwrap()
            .warning()
            .is_none()
    );
    // Outside the board's speed range: the protocol's words.
    let e = check_steer(&mut b, 0.0, 20.0, &held, &model, CHECK).unwrap_err();
    assert!(
        e.to_string().contains("speed 20000 permille is outside"),
        "{e}"
    );
    // Speed 2 plays at 0.5 times the period: the straight gait's joint 0 at 0.4 sin(2 pi / 100) /
    // 0.005 s = 5.02 rad/s is followed (see above), the side gaits' at 0.5 sin(2 pi / 100) / 0.005
    // = 6.28 rad/s is over the MX-28's no-load speed: the left gait, the first checked, is named.
    let side = 0.5 * (TAU / 100.0).sin() / 0.005;
    assert!(peak(0.5) < (1.0 - 0.3 / STALL) * W0 && side > W0);
    let e = check_steer(&mut b, 0.0, 2.0, &held, &model, CHECK).unwrap_err();
    let text = e.to_string();
    assert!(
        text.starts_with("steering at speed 2: slot 1 (\"left\"): at 0.500 s per step (0.500 times the planned 1.000 s) the servos cannot follow it:\n"),
        "{text}"
    );
    assert!(
        text.contains(&format!(
            " at slice 0: {side:.2} rad/s, over the servo's no-load speed {W0:.2} rad/s"
        )),
        "{text}"
    );
    // The right gait alone is as fast: a family of it and the straight gait is refused naming it.
    b.set_steer_family(0, 0, 2, 0.06).unwrap();
    let e = check_steer(&mut b, 0.0, 2.0, &held, &model, CHECK).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("steering at speed 2: slot 2 (\"right\")"),
        "{e}"
    );
    // At speed 1.25 (joint 0 of a side gait at 3.93 rad/s, 0.8 N m left on the line) all follow.
    assert!(
        check_steer(&mut b, 0.0, 1.25, &held, &model, CHECK)
            .unwrap()
            .warning()
            .is_none()
    );
    // Tables the host does not hold: refused naming the straight gait's slot, unless overridden.
    let e = check_steer(&mut b, 0.0, 1.25, &none, &model, CHECK).unwrap_err();
    assert!(matches!(e, RuleError::UnknownTable { slot: 0, .. }), "{e}");
    // The override: the refusal's lines as a warning, then the walk starts.
    b.set_steer_family(0, 1, 2, 0.06).unwrap();
    let checked = check_steer(&mut b, 0.0, 2.0, &held, &model, ALLOW).unwrap();
    let w = board::rules::steer::steer(&mut b, checked)
        .unwrap()
        .unwrap();
    assert!(
        w.to_string().starts_with(
            "steering at speed 2: slot 1 (\"left\"): the servos cannot follow this plan"
        ),
        "{w}"
    );
}

#[test]
fn the_stiffness_bound_is_the_p_gain_register_of_every_servo() {
    // e-manual: P gain / 128 of the 885 PWM units; stall torque per tick (2 pi / 4096 rad).
    let unit = |stall: f64| 1.0 / 128.0 / 885.0 * stall * 4096.0 / TAU;
    let max28 = 16383.0 * unit(2.5);
    let half64 = unit(6.0) / 2.0;
    assert!(units(max28 - 0.01).is_ok());
    assert!(units(235.0).is_ok());
    match units(max28 + 0.05) {
        Err(StiffnessError::AboveRegister { max, .. }) => assert!((max - max28).abs() < 1e-3),
        other => panic!("{other:?}"),
    }
    assert!(units(half64 + 1e-4).is_ok());
    match units(half64 - 1e-4) {
        Err(StiffnessError::BelowRegister { min, .. }) => assert!((min - half64).abs() < 1e-6),
        other => panic!("{other:?}"),
    }
    // 0 is the firmware's "bias off" (no division, the gains kept): taken as it is.
    assert_eq!(units(0.0).unwrap(), 0);
    assert_eq!(units(-0.0).unwrap(), 0);
    // The board's own unit range is still the first check.
    assert!(matches!(units(-0.01), Err(StiffnessError::Limit(_))));
    assert!(matches!(units(f64::NAN), Err(StiffnessError::Limit(_))));
}

use crate::gate;

#[test]
fn a_table_file_meets_the_rules_a_plan_meets_with_the_same_override() {
    // The synthetic gait at 0.4 s per step: joint 0 peaks at slice 0 at 0.4 sin(2 pi / 100) /
    // 0.004 s = 6.28 rad/s, over the MX-28's 5.76. Before the rules checked table bytes, such a
    // table (built with --allow-infeasible) uploaded without the override.
    let model = planner::model::builtin("drosophibot2").unwrap();
    let fast = SyntheticGait::new(100, 0.4).build();
    let e = board::rules::build::table_bytes(fast.clone(), "step table fast.dbgt", &model, CHECK)
        .unwrap_err();
    let text = e.to_string();
    assert!(matches!(e, RuleError::Infeasible { .. }), "{text}");
    assert!(
        text.starts_with("step table fast.dbgt: the servos cannot follow this plan:\n"),
        "{text}"
    );
    assert!(
        text.contains(&format!(
            "at slice 0: {:.2} rad/s, over the servo's no-load speed {W0:.2} rad/s",
            peak(0.4)
        )),
        "{text}"
    );
    assert!(
        text.ends_with(
            "pass --allow-infeasible (Python: allow_infeasible=True) to build it anyway"
        )
    );
    // The override lets it through, the warning in its table; the link takes nothing else.
    let checked =
        board::rules::build::table_bytes(fast.clone(), "step table fast.dbgt", &model, ALLOW)
            .unwrap();
    assert!(matches!(
        checked.warning(),
        Some(Overridden::Infeasible { .. })
    ));
    assert_eq!(checked.bytes(), &fast[..]);
    let mut b = Board::connect(VirtualTransport::new(VirtualRobot::new())).unwrap();
    b.upload(0, &checked, |_, _| {}).unwrap();
    // At its planned period the synthetic gait of 1.0 s is followed: no warning.
    let slow = SyntheticGait::new(100, 1.0).build();
    let ok = board::rules::build::table_bytes(slow, "t", &model, CHECK).unwrap();
    assert_eq!(ok.warning(), None);
}

#[test]
fn a_queued_gait_meets_the_period_rule_of_the_first() {
    let mut b = Board::connect(VirtualTransport::new(VirtualRobot::new())).unwrap();
    let bytes = SyntheticGait::new(100, 1.0).build();
    gate::upload(&mut b, 1, &bytes).unwrap();
    let model = planner::model::builtin("drosophibot2").unwrap();
    let queued = |scale: u16| {
        protocol::QueueCommand(PlayCommand::new(
            1,
            Direction::Forward,
            scale,
            Steps::Count(1),
        ))
    };
    let check = |b: &mut Board<_>, scale, known: Option<&[u8]>, o| {
        board::rules::period::check_queue(b, queued(scale), known, &model, o)
    };
    // 0.4 times the period: joint 0 at 6.28 rad/s, the refusal `dbot run --period` gives.
    let e = check(&mut b, 400, Some(&bytes), CHECK).unwrap_err();
    let by_play = check_play(
        &mut b,
        PlayCommand::new(1, Direction::Forward, 400, Steps::Count(1)),
        Some(&bytes),
        &model,
        CHECK,
    )
    .unwrap_err();
    assert!(matches!(e, RuleError::TooFast { .. }), "{e}");
    assert_eq!(e.to_string(), by_play.to_string());
    // Not held: refused unless overridden, as a play is.
    let e = check(&mut b, 800, None, CHECK).unwrap_err();
    assert!(matches!(e, RuleError::UnknownTable { slot: 1, .. }), "{e}");
    assert!(check(&mut b, 800, None, ALLOW).unwrap().warning().is_some());
    // At the planned period and slower nothing is needed.
    assert!(
        check(&mut b, 1000, None, CHECK)
            .unwrap()
            .warning()
            .is_none()
    );
    assert!(
        check(&mut b, 1500, None, CHECK)
            .unwrap()
            .warning()
            .is_none()
    );
}

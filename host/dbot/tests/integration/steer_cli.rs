//! `dbot steer` as a process against the virtual robot whose flash lives in a file: a family
//! uploaded with `dbot upload`, a steered walk of exactly the steps asked for, and the refusals
//! of the board and the library in their own words.

use crate::cli_support;
use std::f64::consts::PI;
use std::path::Path;

use firmware::testkit::{JOINTS, SyntheticGait};
use protocol::gait::GaitTableBuilder;

use cli_support::{on_virtual as dbot, text};

/// The synthetic gait (20 slices, 0.4 s) with `amp sin(2 pi s / 20) + offset` rad on every
/// angle, written to `name.dbgt`: with offset 0 it shares the straight gait's slice 0.
fn table(dir: &Path, name: &str, amp: f64, offset: f64) -> String {
    let g = SyntheticGait::new(20, 0.4);
    let mut b = GaitTableBuilder::new(name, g.period_s, 0.5, g.joints.clone());
    for s in 0..g.slices {
        let extra = amp * (2.0 * PI * s as f64 / 20.0).sin() + offset;
        let a: Vec<f64> = (0..JOINTS).map(|j| g.angle(s, j) + extra).collect();
        let t: Vec<f64> = (0..JOINTS).map(|j| g.torque(s, j)).collect();
        b.slice(if s < 10 { 0b010_101 } else { 0b101_010 }, &a, &t);
    }
    let path = dir.join(format!("{name}.dbgt"));
    std::fs::write(&path, b.build().unwrap()).unwrap();
    path.display().to_string()
}

#[test]
fn steer_walks_the_steps_asked_for_and_refusals_say_why() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (slot, name, amp, offset) in [
        ("0", "straight", 0.0, 0.0),
        ("1", "left", 0.05, 0.0),
        ("2", "right", -0.05, 0.0),
        ("3", "high", 0.0, 0.1),
    ] {
        let o = dbot(
            d,
            &[
                "upload",
                "--slot",
                slot,
                "--table",
                &table(d, name, amp, offset),
                // Faster than an MX-28 follows (6.2 rad/s): a table file meets the servo rule.
                "--allow-infeasible",
            ],
        );
        assert!(o.status.success(), "{}", text(&o));
    }
    let steer = |family: &str, heading: &str| {
        dbot(
            d,
            &[
                "steer",
                "--family",
                family,
                "--range",
                "0.06",
                "--heading",
                heading,
                "--steps",
                "3",
            ],
        )
    };
    let o = steer("0,1,2", "-0.03");
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("3 step(s), the robot stands"),
        "{}",
        text(&o)
    );
    // The board's refusals: a heading beyond the family, a side gait 0.1 rad off at slice 0.
    let o = steer("0,1,2", "0.1");
    assert!(!o.status.success());
    assert!(
        text(&o).contains("heading 100 mrad is outside the family's range +-60 mrad"),
        "{}",
        text(&o)
    );
    let o = steer("0,3,2", "0");
    assert!(!o.status.success());
    assert!(
        text(&o).contains("gait slot 3 cannot follow the straight gait: joint 0 would jump"),
        "{}",
        text(&o)
    );
    // The library's, before anything is sent.
    let o = steer("0,1,2", "NaN");
    assert!(text(&o).contains("must be a finite number"), "{}", text(&o));
}

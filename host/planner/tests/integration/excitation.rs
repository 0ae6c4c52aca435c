//! Excitation trials (planner::excitation): every goal within its joint's limits and under the
//! servo's no-load speed, the chirp sweeps the frequencies it says (its zero crossings), the
//! standing robot's feet stay where they rest, and the tables build.

use planner::excitation::{ExcitationKind, ExcitationOptions, ExcitationTrial, Motion, excitation};
use planner::model::{Model, builtin};

fn trials(kind: ExcitationKind) -> (Model, Vec<ExcitationTrial>) {
    let m = builtin("drosophibot2").unwrap();
    let e = excitation(&m, kind, &ExcitationOptions::default()).unwrap();
    (m, e.trials)
}

#[test]
fn every_goal_stays_within_the_joint_limits_and_the_servos_speed() {
    let o = ExcitationOptions::default();
    for kind in ExcitationKind::ALL {
        let (m, trials) = trials(kind);
        for t in &trials {
            assert!(t.slices() > 100, "{}", t.name);
            for (j, joint) in m.joints.iter().enumerate() {
                let Some(servo) = joint.servo else { continue };
                let (lo, hi) = joint.limits;
                // The e-manual's no-load speed (MX-28 55 rev/min, MX-64 63; the dynamixel
                // crate's figure) at the options' fraction; the board interpolates linearly, so
                // the speed is the slope between neighbouring slices (and the table loops: last
                // to first too).
                let w0 = f64::from(servo.model.no_load_speed_rad_s());
                let rpm = f64::from(servo.model.no_load_speed_rpm());
                assert!((w0 - rpm * std::f64::consts::TAU / 60.0).abs() < 1e-6 * w0);
                assert!(rpm == 55.0 || rpm == 63.0);
                let n = t.slices();
                let mut fastest = 0.0f64;
                for s in 0..n {
                    let q = t.q[s][j];
                    assert!((lo..=hi).contains(&q), "{} {}: {q}", t.name, joint.name);
                    // Suspended, the goals keep the margin from the limits (but for the
                    // resting posture's own angle, where the transfer starts).
                    let rest = t.q[0][j];
                    let (a, b) = (
                        (lo + o.limit_margin_rad).min(rest),
                        (hi - o.limit_margin_rad).max(rest),
                    );
                    assert!(
                        kind == ExcitationKind::Standing || (a - 1e-12..=b + 1e-12).contains(&q),
                        "{}: {} at slice {s}: {q} outside [{lo}, {hi}] less the margin",
                        t.name,
                        joint.name
                    );
                    let v = (t.q[(s + 1) % n][j] - q).abs() / t.dt_s;
                    fastest = fastest.max(v);
                }
                assert!(
                    fastest <= o.speed_fraction * w0 * (1.0 + 1e-9),
                    "{} {}: {fastest} rad/s over {} x {w0}",
                    t.name,
                    joint.name,
                    o.speed_fraction
                );
            }
            // The planner's own feasibility check (the board's rule) finds nothing either.
            let f = planner::plan::feasibility::check(&m, &t.q, None, t.dt_s);
            assert!(f.is_feasible(), "{}: {:?}", t.name, f.violations);
        }
    }
}

#[test]
fn the_suspended_trials_move_each_joint_kind_and_start_and_end_at_rest() {
    let (m, trials) = trials(ExcitationKind::Suspended);
    let names: Vec<&str> = trials.iter().map(|t| t.name.as_str()).collect();
    // Drosophibot II's servo joints: ThC1 and ThC3 (front legs), CTr, TrF1, FTi (every leg).
    assert_eq!(
        names,
        ["sus-ThC1", "sus-ThC3", "sus-CTr", "sus-TrF1", "sus-FTi"]
    );
    for t in &trials {
        let kind = &t.name[4..];
        let first = &t.q[0];
        let last = &t.q[t.slices() - 1];
        for (j, joint) in m.joints.iter().enumerate() {
            let moved = t.q.iter().any(|q| (q[j] - first[j]).abs() > 1e-6);
            let excited = m.servo_params(j).is_some() && joint.kind.name() == kind;
            assert_eq!(moved, excited, "{}: {}", t.name, joint.name);
            assert!(
                (last[j] - first[j]).abs() < 1e-12,
                "{}: {}",
                t.name,
                joint.name
            );
        }
        // Feet in the air: no leg in stance.
        assert!(t.stance.iter().all(|&s| s == 0));
        assert!(t.name.len() <= 16);
    }
}

#[test]
fn the_chirp_sweeps_the_frequencies_it_says() {
    let (m, trials) = trials(ExcitationKind::Suspended);
    let t = trials.iter().find(|t| t.name == "sus-CTr").unwrap();
    let seg = t
        .segments
        .iter()
        .find(|s| s.joint == "LM_CTr" && matches!(s.motion, Motion::Chirp { .. }))
        .unwrap();
    let Motion::Chirp {
        centre,
        f0_hz,
        f1_hz,
        ..
    } = seg.motion
    else {
        unreachable!()
    };
    assert_eq!((f0_hz, f1_hz), (0.1, 2.0));
    let j = m.joint_index("LM_CTr").unwrap();
    // Zero crossings of the goal about the centre, times by linear interpolation between slices.
    let mut crossings = Vec::new();
    for s in 0..t.slices() - 1 {
        let (t0, t1) = (s as f64 * t.dt_s, (s + 1) as f64 * t.dt_s);
        if t0 < seg.start_s || t1 > seg.end_s {
            continue;
        }
        let (a, b) = (t.q[s][j] - centre, t.q[s + 1][j] - centre);
        if a != 0.0 && a * b <= 0.0 {
            crossings.push(t0 + (t1 - t0) * a / (a - b));
        }
    }
    // A linear chirp of T seconds has (f0 + f1) T / 2 cycles: two crossings each (the end's at
    // the chirp's last instant falls outside the last whole slice or on it).
    let duration = seg.end_s - seg.start_s;
    let cycles = 0.5 * (f0_hz + f1_hz) * duration;
    assert!((cycles - cycles.round()).abs() < 1e-9, "{cycles}");
    let expected = 2.0 * cycles;
    assert!(
        (crossings.len() as f64 - expected).abs() <= 1.0,
        "{} crossings, {expected} expected",
        crossings.len()
    );
    // Between neighbouring crossings half a cycle passes: the frequency there is
    // 1 / (2 dt), the chirp's f0 + (f1 - f0) t / T at their midpoint, within 3 %.
    for w in crossings.windows(2) {
        let mid = 0.5 * (w[0] + w[1]) - seg.start_s;
        let measured = 0.5 / (w[1] - w[0]);
        let said = f0_hz + (f1_hz - f0_hz) * mid / duration;
        assert!(
            (measured - said).abs() < 0.03 * said,
            "at {mid:.2} s: {measured:.4} Hz, the chirp says {said:.4} Hz"
        );
    }
}

#[test]
fn standing_the_feet_stay_where_they_rest_while_the_thorax_heaves() {
    let (m, trials) = trials(ExcitationKind::Standing);
    let o = ExcitationOptions::default();
    assert_eq!(trials.len(), 1);
    let t = &trials[0];
    // Every leg in stance in every slice.
    assert!(t.stance.iter().all(|&s| s == 0b11_1111));
    let heave = t
        .segments
        .iter()
        .find(|s| matches!(s.motion, Motion::Posture { what: "heave", .. }))
        .unwrap();
    // A quarter into the heave the thorax is heave_m up: each foot heave_m lower in its frame
    // and otherwise where it rests (the inverse kinematics' tolerance is 1e-9 of a leg).
    let rest = planner::kinematics::forward(&m, &t.q[0]).feet;
    let s = ((heave.start_s + 0.25 * o.posture_s) / t.dt_s).round() as usize;
    assert!((s as f64 * t.dt_s - heave.start_s - 0.25 * o.posture_s).abs() < 1e-9);
    let up = planner::kinematics::forward(&m, &t.q[s]).feet;
    for (a, b) in rest.iter().zip(&up) {
        assert!((b.z - (a.z - o.heave_m)).abs() < 1e-6, "{a} -> {b}");
        assert!(
            (b.x - a.x).abs() < 1e-6 && (b.y - a.y).abs() < 1e-6,
            "{a} -> {b}"
        );
    }
    // And the tables build (the board's rules: board's tests/excitation_rules.rs).
    let bytes = t.step_table(&m).unwrap();
    let table = protocol::GaitTable::parse(&bytes).unwrap();
    assert_eq!(table.slice_count(), t.slices());
}

//! Whole step cycles: forward kinematics of the solved angles meets every footpath point, the cycle
//! closes, footpaths obey the geometry they were built from, and bad input is named.

use planner::gait::{Footpath, Gait, StepParams};
use planner::kinematics::{IkOptions, LegChain, forward};
use planner::model::{Leg, builtin};
use planner::plan::{Plan, footpaths, periodic_central_difference, plan};
use planner::terrain::Terrain;

fn make(model: &str, terrain: &str) -> Plan {
    let m = builtin(model).unwrap();
    let mut p = StepParams::table1(model);
    p.terrain = planner::terrain::Ground::parse(terrain).unwrap();
    plan(&m, &p).unwrap_or_else(|e| panic!("{model} on {terrain}: {e}"))
}

fn check_closure(plan: &Plan, what: &str) {
    let m = &plan.model;
    let n = plan.slices();
    for s in 0..n {
        let poses = forward(m, &plan.q[s]);
        for (li, leg) in plan.legs.iter().enumerate() {
            let fi = m.feet.iter().position(|f| f.leg == *leg).unwrap();
            let err = (poses.feet[fi].coords - plan.feet[s][li]).norm();
            assert!(
                err <= 1e-6 * m.leg_length(*leg),
                "{what}: {leg:?} slice {s}: {err:e} m"
            );
        }
    }
    // Periodic: carrying on from the last slice into slice 0 again lands on the same angles.
    for (li, leg) in plan.legs.iter().enumerate() {
        let chain = LegChain::new(m, *leg).unwrap();
        let rest: Vec<f64> = chain.actuated.iter().map(|&j| plan.posture.q[j]).collect();
        let mut q: Vec<f64> = chain.actuated.iter().map(|&j| plan.q[n - 1][j]).collect();
        chain
            .solve(&plan.feet[0][li], &mut q, &rest, &IkOptions::default())
            .unwrap();
        for (k, &j) in chain.actuated.iter().enumerate() {
            let d = (q[k] - plan.q[0][j]).abs();
            assert!(
                d < 1e-6,
                "{what}: {leg:?} joint {} does not close the cycle: {d:e} rad",
                m.joints[j].name
            );
        }
    }
    // Angles stay within limits.
    for q in &plan.q {
        for (j, joint) in m.joints.iter().enumerate() {
            assert!(
                q[j] >= joint.limits.0 - 1e-12 && q[j] <= joint.limits.1 + 1e-12,
                "{what}: {}",
                joint.name
            );
        }
    }
}

#[test]
fn robot_flat_and_ball_close_exactly() {
    check_closure(&make("drosophibot2", "flat"), "drosophibot2 flat");
    check_closure(&make("drosophibot2", "ball"), "drosophibot2 ball");
}

#[test]
fn fly_flat_and_ball_close_exactly() {
    check_closure(&make("scale-drosophila", "flat"), "scale-drosophila flat");
    check_closure(&make("scale-drosophila", "ball"), "scale-drosophila ball");
}

#[test]
fn incline_tilts_gravity_only() {
    let flat = make("drosophibot2", "flat");
    let inc = make("drosophibot2", "incline:15");
    assert_eq!(flat.q, inc.q);
    let a = 15f64.to_radians();
    // Thorax parallel to a slope rising forward: gravity pulls backward and down.
    assert!((inc.gravity - nalgebra::Vector3::new(-a.sin(), 0.0, -a.cos()) * 9.81).norm() < 1e-12);
    assert!((flat.gravity.norm() - 9.81).abs() < 1e-12);
}

fn paths(
    model: &str,
    terrain: &str,
    edit: impl Fn(&mut StepParams),
) -> (
    StepParams,
    Vec<Footpath>,
    Option<nalgebra::Vector3<f64>>,
    Terrain,
) {
    let m = builtin(model).unwrap();
    let mut p = StepParams::table1(model);
    p.terrain = planner::terrain::Ground::parse(terrain).unwrap();
    edit(&mut p);
    let t = p
        .terrain
        .plan_terrain(p.ball_radius_m, p.ball_offset_m)
        .unwrap();
    let post = planner::kinematics::resting_posture(&m, &t, &|l| p.foot_goal(l)).unwrap();
    let c = post.ball_centre;
    (p.clone(), footpaths(&p, &t, &post), c, t)
}

#[test]
fn straight_stance_is_centred_and_at_walking_speed() {
    for backward in [false, true] {
        let (p, fps, _, _) = paths("drosophibot2", "flat", |p| {
            if backward {
                p.translation_m = -p.translation_m;
            }
        });
        let v = p.translation_m / p.stance_s();
        for fp in &fps {
            // Touch-down and lift-off (in local time) straddle the resting foot symmetrically.
            let t0 = fp.phase * fp.period;
            let (td, st0) = fp.at(t0);
            let (lo, _) = fp.at(t0 + p.stance_s() - 1e-12);
            assert!(st0);
            assert!(((td + lo) / 2.0 - fp.rest).norm() < 1e-9);
            assert!(
                ((td - lo).x - p.translation_m).abs() < 1e-9,
                "stance length = body translation"
            );
            // Constant velocity -v along x (forward walking moves the foot backward).
            let (a, _) = fp.at(t0 + 0.2);
            let (b, _) = fp.at(t0 + 0.3);
            assert!(((b - a) / 0.1 - nalgebra::Vector3::new(-v, 0.0, 0.0)).norm() < 1e-9);
        }
    }
}

#[test]
fn swing_reaches_step_height_and_joins_stance_smoothly() {
    let (p, fps, _, _) = paths("drosophibot2", "flat", |_| {});
    for fp in &fps {
        let t0 = fp.phase * fp.period;
        let (apex, st) = fp.at(t0 + p.stance_s() + p.swing_s / 2.0);
        assert!(!st);
        let want = -p.body_height_m.get(fp.leg) + p.step_height_m.get(fp.leg);
        assert!(
            (apex.z - want).abs() < 1e-12,
            "{:?} apex {} vs {}",
            fp.leg,
            apex.z,
            want
        );
        // Velocity continuous across lift-off and touch-down (quintics match the stance).
        for edge in [t0 + p.stance_s(), t0 + fp.period] {
            let h = 1e-6;
            let before = (fp.at(edge - h).0 - fp.at(edge - 2.0 * h).0) / h;
            let after = (fp.at(edge + 2.0 * h).0 - fp.at(edge + h).0) / h;
            assert!(
                (before - after).norm() < 1e-3 * before.norm().max(1e-3),
                "{:?} at {edge}",
                fp.leg
            );
        }
    }
}

#[test]
fn curves_and_ball_keep_stance_feet_on_the_ground_motion() {
    // A left turn: stance feet circle the instantaneous centre (0, v/w, 0).
    let (p, fps, _, _) = paths("drosophibot2", "flat", |p| p.rotation_rad = 0.2);
    let icr = nalgebra::Vector3::new(0.0, p.translation_m / p.rotation_rad, 0.0);
    for fp in &fps {
        let t0 = fp.phase * fp.period;
        let r0 = (fp.at(t0).0 - icr).norm();
        for k in 1..10 {
            let (x, st) = fp.at(t0 + p.stance_s() * k as f64 / 10.0);
            assert!(st);
            assert!(((x - icr).norm() - r0).abs() < 1e-12);
        }
    }
    // On the ball, stance feet stay on the sphere.
    let (p, fps, c, t) = paths("drosophibot2", "ball", |_| {});
    let (Terrain::Ball { radius_m, .. }, Some(c)) = (t, c) else {
        panic!()
    };
    for fp in &fps {
        let t0 = fp.phase * fp.period;
        for k in 0..10 {
            let (x, _) = fp.at(t0 + p.stance_s() * k as f64 / 10.0);
            assert!(((x - c).norm() - radius_m).abs() < 1e-12);
        }
    }
}

#[test]
fn gaits_by_phase_offsets() {
    let tripod_a = [Leg::LF, Leg::RM, Leg::LH];
    let tripod_b = [Leg::RF, Leg::LM, Leg::RH];
    for (a, b) in tripod_a.iter().zip(&tripod_b) {
        assert_eq!(Gait::TRIPOD.phase(*a), Gait::TRIPOD.phase(tripod_a[0]));
        assert!((Gait::TRIPOD.phase(*b) - Gait::TRIPOD.phase(*a) - 0.5).rem_euclid(1.0) < 1e-12);
    }
    // Wave: six distinct phases, hind first, one sixth apart.
    let mut ph: Vec<f64> = Leg::ALL.iter().map(|l| Gait::WAVE.phase(*l)).collect();
    ph.sort_by(f64::total_cmp);
    for w in ph.windows(2) {
        assert!((w[1] - w[0] - 1.0 / 6.0).abs() < 1e-12);
    }
    assert!(Gait::WAVE.phase(Leg::LH) < Gait::WAVE.phase(Leg::LM));
    // Tetrapod pairs swing together.
    for (a, b) in [(Leg::LH, Leg::RM), (Leg::LM, Leg::RF), (Leg::LF, Leg::RH)] {
        assert!(
            (Gait::TETRAPOD.phase(a) - Gait::TETRAPOD.phase(b)).abs() < 1e-12,
            "{a:?} {b:?}"
        );
    }
    // With duty 0.6 a tripod always has at least three feet down.
    let pl = make("drosophibot2", "flat");
    for s in &pl.stance {
        assert!(s.iter().filter(|x| **x).count() >= 3);
    }
    assert_eq!(
        Gait::parse("0.25:0.5"),
        Some(Gait {
            phi_i: 0.25,
            phi_c: 0.5
        })
    );
}

#[test]
fn central_differences_match_calculus() {
    // x = sin(w t): the periodic central difference is sin(w dt)/(w dt) times the exact derivative.
    let n = 64;
    let period = 1.3;
    let dt = period / n as f64;
    let w = 2.0 * std::f64::consts::PI / period;
    let x: Vec<Vec<f64>> = (0..n).map(|i| vec![(w * i as f64 * dt).sin()]).collect();
    let d = periodic_central_difference(&x, dt);
    let factor = (w * dt).sin() / (w * dt);
    for (i, v) in d.iter().enumerate() {
        let exact = w * (w * i as f64 * dt).cos() * factor;
        assert!((v[0] - exact).abs() < 1e-12, "slice {i}");
    }
}

#[test]
fn any_number_of_slices() {
    let m = builtin("drosophibot2").unwrap();
    for n in [7, 1000] {
        let mut p = StepParams::table1("drosophibot2");
        p.slices = n;
        let pl = plan(&m, &p).unwrap();
        assert_eq!(pl.q.len(), n);
        assert!((pl.dt * n as f64 - p.period_s()).abs() < 1e-12);
    }
}

#[test]
fn impossible_parameters_name_the_field() {
    let m = builtin("drosophibot2").unwrap();
    let err = |edit: &dyn Fn(&mut StepParams)| {
        let mut p = StepParams::table1("drosophibot2");
        edit(&mut p);
        plan(&m, &p).unwrap_err().to_string()
    };
    assert!(err(&|p| p.duty = 1.2).contains("duty"));
    assert!(err(&|p| p.duty = 0.0).contains("duty"));
    assert!(err(&|p| p.swing_s = -0.5).contains("swing_s"));
    assert!(err(&|p| p.slices = 2).contains("slices"));
    let lava = planner::gait::ParamsFile::from_toml("terrain = \"lava\"", "p.toml").unwrap_err();
    assert!(
        lava.to_string().contains("unknown terrain `lava`"),
        "{lava}"
    );
    let blocks = err(&|p| p.terrain = planner::terrain::Ground::parse("blocks").unwrap());
    assert!(blocks.contains("the planner plans for flat, incline and the held ball only"));
    // A 0.5 m stride is beyond the legs: the error names a leg and a slice.
    let e = err(&|p| p.translation_m = 0.5);
    assert!(
        e.contains("leg ") && e.contains("slice ") && e.contains("unreachable"),
        "{e}"
    );
    // A foot 2 m below the thorax: the resting posture names the leg.
    let e = err(&|p| p.body_height_m = planner::gait::PerPair::all(2.0));
    assert!(e.contains("leg ") && e.contains("resting posture"), "{e}");
}

#[test]
fn csv_writers_follow_the_issue_and_take_extra_columns() {
    let pl = make("drosophibot2", "flat");
    let mut buf = Vec::new();
    let torque: Vec<Vec<f64>> = vec![vec![1.5; pl.model.joints.len()]; pl.slices()];
    planner::plan_dir::write_joints_csv(
        &mut buf,
        &pl,
        &[planner::plan_dir::ExtraColumn {
            name: "torque_nm",
            values: &torque,
        }],
    )
    .unwrap();
    let text = String::from_utf8(buf).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("slice,time_s,leg,joint,angle_rad,velocity_rad_s,accel_rad_s2,stance,torque_nm")
    );
    assert_eq!(lines.count(), pl.slices() * pl.model.joints.len());
    let mut buf = Vec::new();
    planner::plan_dir::write_feet_csv(&mut buf, &pl, &[]).unwrap();
    let text = String::from_utf8(buf).unwrap();
    assert!(text.starts_with("slice,time_s,leg,x_m,y_m,z_m,stance\n"));
    let short = vec![vec![0.0; 3]; pl.slices()];
    let e = planner::plan_dir::write_feet_csv(
        Vec::new(),
        &pl,
        &[planner::plan_dir::ExtraColumn {
            name: "grf_x_n",
            values: &short,
        }],
    )
    .unwrap_err();
    assert!(e.to_string().contains("grf_x_n"));
}

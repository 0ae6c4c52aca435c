//! Parallel elasticity on whole models (paper section 3.1.2): the presets carry the paper's values,
//! a spring without an equilibrium angle takes the plan's resting posture, and the spring torque
//! and the actuator's share follow the hand calculation T_spring = -k_s (q - q_eq).

use planner::dynamics::{DynamicsOptions, plan_inputs, solve_cycle};
use planner::gait::StepParams;
use planner::model::spring::{SpringError, resolve_equilibria, with_parallel_springs};
use planner::model::{
    Actuation, EquilibriumSource, JointKind, Leg, SpringPreset, SpringSpec, builtin, from_toml_str,
    to_toml_string,
};

#[test]
fn presets_are_the_papers_values() {
    // Paper section 3.1.2: k_joint = 1 N m/rad (Drosophibot II), 3.8e-8 N m/rad (Scale-Drosophila).
    let robot = builtin("drosophibot2").unwrap();
    let fly = builtin("scale-drosophila").unwrap();
    assert_eq!(
        SpringSpec::parse("paper").unwrap().stiffness(&robot),
        Ok(1.0)
    );
    assert_eq!(
        SpringSpec::parse("paper").unwrap().stiffness(&fly),
        Ok(3.8e-8)
    );
    assert_eq!(
        SpringSpec::parse("scale-drosophila").unwrap(),
        SpringSpec::Preset(SpringPreset::ScaleDrosophila)
    );
    assert_eq!(
        SpringSpec::parse("0.25").unwrap(),
        SpringSpec::Stiffness(0.25)
    );
    assert!(matches!(
        SpringSpec::parse("-1"),
        Err(SpringError::Unknown { .. })
    ));
    let mut other = robot.clone();
    other.name = "my-robot".into();
    assert!(matches!(
        SpringSpec::Paper.stiffness(&other),
        Err(SpringError::NoPaperValue { .. })
    ));
}

#[test]
fn the_fly_models_actuator_stiffness_is_the_papers_with_its_source() {
    let fly = builtin("scale-drosophila").unwrap();
    let mut actuated = 0;
    for j in &fly.joints {
        match &j.actuation {
            Actuation::Actuated { stiffness, .. } => {
                assert_eq!(*stiffness, 3.8e-8, "{}", j.name);
                actuated += 1;
            }
            Actuation::Fixed { .. } => {}
        }
    }
    // 6 legs x 6 actuated DoF (ThC1-3, CTr, TrF, FTi).
    assert_eq!(actuated, 36);
    let text = include_str!("../../models/scale-drosophila.toml");
    assert!(text.contains("section 3.1.2") && !text.contains("PLACEHOLDER"));
}

#[test]
fn spring_without_equilibrium_takes_the_resting_posture_and_round_trips() {
    let robot = builtin("drosophibot2").unwrap();
    let sprung = with_parallel_springs(&robot, 1.0, EquilibriumSource::RestingPosture);
    let text = to_toml_string(&sprung, "", &|_| String::new());
    assert!(text.contains("equilibrium = \"rest\""));
    assert!(!text.contains("equilibrium_rad"));
    let back = from_toml_str(&text, "round-trip").unwrap();
    let springs = |m: &planner::model::Model| m.joints.iter().map(|j| j.spring).collect::<Vec<_>>();
    assert_eq!(springs(&back), springs(&sprung));
    assert_eq!(springs(&back).iter().flatten().count(), 22);

    let both = "equilibrium_rad = 0.1\nequilibrium = \"rest\"";
    let bad = text.replacen("equilibrium = \"rest\"", both, 1);
    let e = from_toml_str(&bad, "both.toml").unwrap_err().to_string();
    assert!(
        e.contains("both.toml") && e.contains("spring.equilibrium"),
        "{e}"
    );
}

#[test]
fn spring_torque_is_minus_k_times_the_deflection_from_rest() {
    // Hand calculation on the fly's 3.8e-8 N m/rad: a joint 0.25 rad past its resting angle
    // feels -3.8e-8 * 0.25 = -9.5e-9 N m; one 0.1 rad short of it +3.8e-9 N m; fixed joints none.
    let fly = builtin("scale-drosophila").unwrap();
    let mut m = with_parallel_springs(&fly, 3.8e-8, EquilibriumSource::RestingPosture);
    let rest: Vec<f64> = (0..m.joints.len()).map(|j| 0.01 * j as f64).collect();
    resolve_equilibria(&mut m, &rest, std::slice::from_ref(&rest));
    let mut q = rest.clone();
    q[0] += 0.25;
    q[1] -= 0.1;
    let t = planner::dynamics::problem::spring_torques(&m, &q);
    assert!((t[0] - -9.5e-9).abs() < 1e-22, "{}", t[0]);
    assert!((t[1] - 3.8e-9).abs() < 1e-22, "{}", t[1]);
    for (j, joint) in m.joints.iter().enumerate().skip(2) {
        match joint.actuation {
            Actuation::Actuated { .. } => assert!(t[j].abs() < 1e-24, "{}", joint.name),
            Actuation::Fixed { .. } => assert_eq!(t[j], 0.0),
        }
    }
}

#[test]
fn planned_springs_rest_at_the_resting_posture_and_enter_the_actuator_torque() {
    // Plan the robot with 1 N m/rad: every spring's equilibrium is the resting posture's angle,
    // and per slice actuator torque = axis moment - spring torque, spring = -(q - q_rest).
    let robot = builtin("drosophibot2").unwrap();
    let sprung = SpringSpec::Paper
        .apply(&robot, EquilibriumSource::RestingPosture)
        .unwrap();
    let mut p = StepParams::table1(&robot.name);
    p.slices = 20;
    let plan = planner::plan::plan(&sprung, &p).unwrap();
    let cycle = solve_cycle(
        &plan.model,
        &plan_inputs(&plan),
        &DynamicsOptions::default(),
    )
    .unwrap();
    for (j, joint) in plan.model.joints.iter().enumerate() {
        match (&joint.actuation, joint.spring) {
            (Actuation::Actuated { .. }, Some(s)) => {
                assert_eq!(s.stiffness, 1.0);
                assert_eq!(s.equilibrium, plan.posture.q[j], "{}", joint.name);
            }
            (Actuation::Fixed { .. }, None) => {}
            (a, s) => panic!("{}: {a:?} with spring {s:?}", joint.name),
        }
    }
    for (s, sol) in cycle.slices.iter().enumerate() {
        for j in 0..plan.model.joints.len() {
            if plan.model.joints[j].spring.is_some() {
                let expected = -(plan.q[s][j] - plan.posture.q[j]);
                assert!((sol.spring_torque[j] - expected).abs() < 1e-12);
                let act = sol.axis_moment[j] - sol.spring_torque[j];
                assert!((sol.torque[j] - act).abs() < 1e-12);
            }
        }
    }
    // V* uses the joint stiffness, actuator + 1 N m/rad.
    assert!(
        cycle
            .stiffness
            .iter()
            .zip(&plan.model.joints)
            .all(|(k, j)| match (k, &j.actuation) {
                (Some(k), Actuation::Actuated { stiffness, .. }) =>
                    (k - (stiffness + 1.0)).abs() < 1e-12,
                (None, Actuation::Fixed { .. }) => true,
                _ => false,
            })
    );
}

#[test]
fn dead_fly_equilibrium_and_its_spring_torque_by_hand() {
    // The dead-fly proxy (solver.md: CTr about -35 deg, FTi about its minimum angle - 20 deg;
    // other joints the middle of their range over the step) on the fly's 3.8e-8 N m/rad, with a
    // hand-made two-slice "step" in which every joint spans -0.3 .. 0.5 rad.
    let fly = builtin("scale-drosophila").unwrap();
    let mut m = with_parallel_springs(&fly, 3.8e-8, EquilibriumSource::DeadFly);
    let n = m.joints.len();
    let rest = vec![0.0; n];
    let step = vec![vec![-0.3; n], vec![0.5; n]];
    resolve_equilibria(&mut m, &rest, &step);
    let joint = |kind: JointKind| {
        m.joints
            .iter()
            .position(|j| j.leg == Leg::LF && j.kind == kind)
            .unwrap()
    };
    let (ctr, fti, thc1) = (
        joint(JointKind::CTr),
        joint(JointKind::FTi),
        joint(JointKind::ThC1),
    );
    let eq = |j: usize| m.joints[j].spring.unwrap().equilibrium;
    // -35 deg = -0.610865238 rad; FTi: -0.3 - 20 deg = -0.3 - 0.349065850 = -0.649065850 rad;
    // ThC1: (-0.3 + 0.5) / 2 = 0.1 rad.
    assert!((eq(ctr) - -0.610_865_238).abs() < 1e-9, "{}", eq(ctr));
    assert!((eq(fti) - -0.649_065_850).abs() < 1e-9, "{}", eq(fti));
    assert!((eq(thc1) - 0.1).abs() < 1e-15, "{}", eq(thc1));
    // tau = -k (theta - theta0) at theta = 0.1 rad on the FTi:
    // -3.8e-8 x (0.1 + 0.649065850) = -3.8e-8 x 0.749065850 = -2.846450e-8 N m;
    // on the CTr at 0: -3.8e-8 x 0.610865238 = -2.321288e-8 N m; on the ThC1 at 0.1: 0.
    let mut q = vec![0.0; n];
    q[fti] = 0.1;
    q[thc1] = 0.1;
    let t = planner::dynamics::problem::spring_torques(&m, &q);
    assert!((t[fti] - -2.846_450e-8).abs() < 1e-14, "{}", t[fti]);
    assert!((t[ctr] - -2.321_288e-8).abs() < 1e-14, "{}", t[ctr]);
    assert!(t[thc1].abs() < 1e-22, "{}", t[thc1]);

    // The model file names the source and reads back as the same proxy.
    let text = to_toml_string(&m, "", &|_| String::new());
    assert!(text.contains("equilibrium = \"dead_fly\""));
    let back = from_toml_str(&text, "dead-fly.toml").unwrap();
    assert!(
        back.joints
            .iter()
            .filter_map(|j| j.spring)
            .all(|s| s.equilibrium_from == EquilibriumSource::DeadFly)
    );
}

#[test]
fn planned_dead_fly_springs_hold_the_proxy_angles() {
    // Planned on the robot: every CTr spring rests at -35 deg, every FTi spring 20 deg below that
    // joint's smallest planned angle, the others at the middle of their planned range.
    let robot = builtin("drosophibot2").unwrap();
    let sprung = SpringSpec::Paper
        .apply(&robot, EquilibriumSource::DeadFly)
        .unwrap();
    let mut p = StepParams::table1(&robot.name);
    p.slices = 20;
    let plan = planner::plan::plan(&sprung, &p).unwrap();
    let mut checked = 0;
    for (j, joint) in plan.model.joints.iter().enumerate() {
        let Some(s) = joint.spring else { continue };
        let lo = plan.q.iter().map(|q| q[j]).fold(f64::INFINITY, f64::min);
        let hi = plan
            .q
            .iter()
            .map(|q| q[j])
            .fold(f64::NEG_INFINITY, f64::max);
        let want = match joint.kind {
            JointKind::CTr => -35f64.to_radians(),
            JointKind::FTi => lo - 20f64.to_radians(),
            _ => 0.5 * (lo + hi),
        };
        assert!((s.equilibrium - want).abs() < 1e-12, "{}", joint.name);
        checked += 1;
    }
    assert_eq!(checked, 22);
}

/// `--spring 1e300` ran the posture solve for hours (issue #30): a stiffness beyond the model's
/// own bound for a parallel spring (1e6 N m/rad, `model::ranges`) is refused where it is parsed.
#[test]
fn a_spring_stiffer_than_any_model_may_have_is_refused_where_it_is_parsed() {
    assert_eq!(
        SpringSpec::parse("1e6").unwrap(),
        SpringSpec::Stiffness(1e6)
    );
    for huge in ["1e300", "1000001", "inf"] {
        let e = SpringSpec::parse(huge).unwrap_err();
        let words = e.to_string();
        assert!(
            matches!(e, SpringError::OutOfRange { .. }) && words.contains("0 ..= 1e6 N m/rad"),
            "{huge}: {words}"
        );
    }
}

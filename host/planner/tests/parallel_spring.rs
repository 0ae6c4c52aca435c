//! Parallel elasticity on whole models (paper section 3.1.2): the presets carry the paper's values,
//! a spring without an equilibrium angle takes the plan's resting posture, and the spring torque
//! and the actuator's share follow the hand calculation T_spring = -k_s (q - q_eq).

use planner::dynamics::{DynamicsOptions, plan_inputs, solve_cycle};
use planner::gait::StepParams;
use planner::model::spring::{SpringError, resolve_equilibria, with_parallel_springs};
use planner::model::{
    Actuation, EquilibriumSource, SpringPreset, SpringSpec, builtin, from_toml_str, to_toml_string,
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
    let text = include_str!("../models/scale-drosophila.toml");
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

//! Contact and torque constraints and the slip / saturation report, and errors on bad input.

use crate::dynamics_support;
use dynamics_support::{standing_pose, toy_hexapod, trajectory};
use nalgebra::Vector3;
use planner::dynamics::{
    DynamicsError, DynamicsOptions, SliceInput, TorqueLimits, solve_cycle, solve_slice,
};
use planner::model::Model;

fn cycle(model: &Model, n: usize) -> Vec<SliceInput> {
    let q0 = standing_pose(model);
    (0..n)
        .map(|i| {
            let (q, qd, qdd) = trajectory(model, &q0, 0.05 * i as f64);
            let mut s = SliceInput::still(model, q);
            s.qd = qd;
            s.qdd = qdd;
            s.stance = (0..6usize)
                .map(|f| i.is_multiple_of(2) || f.is_multiple_of(2))
                .collect();
            s
        })
        .collect()
}

#[test]
fn friction_cone_holds_and_report_lists_slips_when_off() {
    let model = toy_hexapod();
    let inputs = cycle(&model, 10);
    let mu = 0.15;
    let off = solve_cycle(
        &model,
        &inputs,
        &DynamicsOptions {
            mu,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(
        !off.report.slips.is_empty(),
        "expected unconstrained GRF outside a mu = 0.15 cone"
    );
    for slip in &off.report.slips {
        let s = &off.slices[slip.slice];
        let f = model
            .feet
            .iter()
            .position(|f| f.leg.name() == slip.leg)
            .unwrap();
        let g = s.grf[f];
        assert!(g.xy().norm() > mu * g.z || g.z < 0.0);
    }
    let on = solve_cycle(
        &model,
        &inputs,
        &DynamicsOptions {
            mu,
            friction_cone: true,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(on.report.slips.is_empty(), "{:?}", on.report.slips);
    for (s, inp) in on.slices.iter().zip(&inputs) {
        for (g, st) in s.grf.iter().zip(&inp.stance) {
            if *st {
                assert!(g.xy().norm() <= mu * g.z * (1.0 + 1e-6) + 1e-9, "{g}");
            }
        }
    }
    // The constrained optimum costs at least as much as the unconstrained one.
    for (a, b) in off.slices.iter().zip(&on.slices) {
        assert!(b.v_star >= a.v_star * (1.0 - 1e-7));
    }
}

#[test]
fn torque_limits_are_reported_and_enforced() {
    let model = toy_hexapod();
    let inputs = cycle(&model, 6);
    let limits = TorqueLimits::PerJoint(vec![Some(0.8); model.joints.len()]);
    let off = solve_cycle(
        &model,
        &inputs,
        &DynamicsOptions {
            torque_limits: limits.clone(),
            ..Default::default()
        },
    )
    .unwrap();
    let peak = off
        .slices
        .iter()
        .flat_map(|s| s.torque.iter())
        .fold(0.0f64, |m, t| m.max(t.abs()));
    assert!(peak > 0.8, "peak {peak}: the limit would not bind");
    assert!(!off.report.saturations.is_empty());
    let opts = DynamicsOptions {
        torque_limits: limits,
        enforce_torque_limits: true,
        ..Default::default()
    };
    let on = solve_cycle(&model, &inputs, &opts).unwrap();
    for s in &on.slices {
        for t in &s.torque {
            assert!(t.abs() <= 0.8 * (1.0 + 1e-6), "{t}");
        }
    }
    // A limit no load sharing can meet is an error naming the slice.
    let opts = DynamicsOptions {
        torque_limits: TorqueLimits::PerJoint(vec![Some(1e-3); model.joints.len()]),
        enforce_torque_limits: true,
        ..Default::default()
    };
    match solve_cycle(&model, &inputs, &opts) {
        Err(DynamicsError::Infeasible {
            slices,
            constraints,
            need,
            advice,
        }) => {
            assert!(slices.starts_with('0'), "{slices}");
            assert_eq!(constraints, "torque limits");
            assert!(need.contains("limit 1.000e-3"), "{need}");
            assert!(advice.contains("stronger actuators"), "{advice}");
        }
        other => panic!("expected an infeasibility error naming slice 0, got {other:?}"),
    }
}

#[test]
fn push_only_feet_never_pull() {
    let model = toy_hexapod();
    let mut inputs = cycle(&model, 8);
    for s in &mut inputs {
        // Throw the body upward and sideways so that some feet would pull without the constraint.
        s.thorax.linear_acceleration = Vector3::new(0.0, 6.0, 0.0);
    }
    let off = solve_cycle(&model, &inputs, &DynamicsOptions::default()).unwrap();
    assert!(
        off.slices.iter().any(|s| s.grf.iter().any(|g| g.z < 0.0)),
        "no pulling foot to prevent"
    );
    let on = solve_cycle(
        &model,
        &inputs,
        &DynamicsOptions {
            push_only: true,
            ..Default::default()
        },
    )
    .unwrap();
    for s in &on.slices {
        assert!(s.grf.iter().all(|g| g.z >= -1e-9 * g.norm().max(1.0)));
    }
}

#[test]
fn parallel_solve_gives_the_same_answer() {
    let model = toy_hexapod();
    let inputs = cycle(&model, 12);
    let a = solve_cycle(&model, &inputs, &DynamicsOptions::default()).unwrap();
    let b = solve_cycle(
        &model,
        &inputs,
        &DynamicsOptions {
            parallel: true,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(a, b);
}

#[test]
fn bad_input_is_an_error_naming_the_slice() {
    let model = toy_hexapod();
    let mut inputs = cycle(&model, 4);
    inputs[2].qd.pop();
    match solve_cycle(&model, &inputs, &DynamicsOptions::default()) {
        Err(DynamicsError::InputLength {
            slice: 2,
            field: "qd",
            expected: 24,
            got: 23,
        }) => {}
        other => panic!("{other:?}"),
    }
    let mut inputs = cycle(&model, 4);
    inputs[1].q[5] = f64::NAN;
    let e = solve_cycle(&model, &inputs, &DynamicsOptions::default()).unwrap_err();
    assert!(
        e.to_string().contains("slice 1") && e.to_string().contains(&model.joints[5].name),
        "{e}"
    );
    // Two feet cannot hold the body: the error says which slice and which feet.
    let mut inputs = cycle(&model, 4);
    inputs[3].stance = vec![true, false, false, false, true, false];
    let e = solve_cycle(&model, &inputs, &DynamicsOptions::default()).unwrap_err();
    assert!(
        matches!(e, DynamicsError::Unbalanced { slice: 3, .. }),
        "{e}"
    );
    assert!(e.to_string().contains("LF RM"), "{e}");
}

#[test]
fn a_stance_leg_with_too_few_actuated_joints_is_not_unique() {
    // Lock the CTr and FTi of every leg: a stance leg can then shift load for free.
    let mut model = toy_hexapod();
    for j in &mut model.joints {
        if matches!(
            j.kind,
            planner::model::JointKind::CTr | planner::model::JointKind::FTi
        ) {
            j.actuation = planner::model::Actuation::Fixed { angle: 0.0 };
        }
    }
    let s = SliceInput::still(&model, standing_pose(&model));
    let e = solve_slice(&model, &s, &DynamicsOptions::default(), 7).unwrap_err();
    assert!(
        matches!(e, DynamicsError::NotUnique { slice: 7, .. }),
        "{e}"
    );
}

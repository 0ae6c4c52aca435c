//! The scale fly at the physics robot's 1 ms timestep (issue 17): its joints' inertias are tiny
//! (down to 5e-15 kg m^2 against 3.8e-8 N m/rad), so a position actuator on one rings at up to
//! 2740 rad/s, and MuJoCo integrates the spring explicitly: unstable past omega dt = 2. The
//! physics robot refuses such a timestep naming the model, the joint and the stable timestep
//! (the timestep rule's `MAX_OMEGA_DT`, host/physics/src/timestep.rs); MuJoCo itself, on the fly's MJCF, agrees: at 1 ms the held
//! stance blows up, at the timestep the error names it stands still.

use mujoco_rs::prelude::*;
use physics::{PhysicsError, PhysicsRobot, Plant, TIMESTEP_S};
use planner::model::{MjcfOptions, Model, builtin, to_mjcf};
use planner::terrain::Ground;

/// The fly's exported MJCF at `dt` held in its stance by its position actuators (ctrl = the
/// keyframe's angles), gravity ramped in over 0.5 s, for 1 s: the thorax height (m) and the
/// largest joint speed seen (rad/s), or `None` if the state stopped being finite.
fn hold(model: &Model, dt: f64) -> Option<(f64, f64)> {
    let mut options = MjcfOptions::stance(model, &Ground::Flat).unwrap();
    options.timestep_s = dt;
    let mj = MjModel::from_xml_string(&to_mjcf(model, &options)).unwrap();
    let mut d = MjData::new(Box::new(mj));
    d.reset_keyframe(0).unwrap();
    let g = d.model_opt().gravity;
    let mut fastest = 0.0f64;
    while d.time() < 1.0 {
        let ramp = (d.time() / 0.5).min(1.0);
        d.model_opt_mut().gravity = g.map(|x| x * ramp);
        d.step();
        if !d.qpos().iter().all(|x| x.is_finite()) {
            return None;
        }
        // After the ramp: the stance should be still.
        if d.time() > 0.7 {
            fastest = d.qvel()[6..].iter().fold(fastest, |a, &v| a.max(v.abs()));
        }
    }
    Some((d.qpos()[2], fastest))
}

#[test]
fn the_fly_at_1_ms_is_refused_naming_the_stable_timestep_and_mujoco_agrees() {
    let fly = builtin("scale-drosophila").unwrap();
    let err = PhysicsRobot::new(&fly, &Ground::Flat).unwrap_err();
    let text = err.to_string();
    let PhysicsError::Timestep {
        model,
        timestep_ms,
        stable_ms,
        ..
    } = err
    else {
        panic!("not a timestep error: {text}");
    };
    assert_eq!(model, "scale-drosophila");
    assert_eq!(timestep_ms, TIMESTEP_S * 1e3);
    assert!(
        text.contains("scale-drosophila") && text.contains("at most"),
        "{text}"
    );
    // 0.3 / 2740 rad/s = 0.11 ms (hand: sqrt(3.8e-8 / 5.06e-15) = 2740).
    assert!((0.09..0.13).contains(&stable_ms), "{text}");
    eprintln!("{text}");

    // MuJoCo alone: the stance held at 1 ms does not stay (the thorax starts 1.3 mm up).
    let h0 = MjcfOptions::stance(&fly, &Ground::Flat).unwrap();
    let start = {
        let mj = MjModel::from_xml_string(&to_mjcf(&fly, &h0)).unwrap();
        let mut d = MjData::new(Box::new(mj));
        d.reset_keyframe(0).unwrap();
        d.qpos()[2]
    };
    match hold(&fly, 1e-3) {
        None => {}
        Some((h, v)) => assert!(
            (h - start).abs() > 2.0 * start || v > 50.0,
            "1 ms: height {h} m from {start} m, joint speed {v} rad/s: looks stable"
        ),
    }
    // At the named timestep it stands still (measured 0.07 rad/s at 0.1 ms; 22 rad/s at 0.5 ms).
    let (h, v) = hold(&fly, stable_ms * 1e-3).expect("finite at the stable timestep");
    assert!(
        (h - start).abs() < 0.2 * start && v < 1.0,
        "{stable_ms} ms: height {h} m from {start} m, joint speed {v} rad/s"
    );
    // At that timestep the physics robot gets past the check (and stops at the servo map the fly
    // has none of).
    let mut options = PhysicsRobot::options(&fly, &Ground::Flat).unwrap();
    options.timestep_s = stable_ms * 1e-3;
    assert!(matches!(
        Plant::new(&fly, &options),
        Err(PhysicsError::NoServo { .. })
    ));
}

#[test]
fn drosophibot_at_1_ms_is_far_inside_the_stable_timestep() {
    // Its stiffest joint (kp 14.3 N m/rad on 3.6e-3 kg m^2, mostly the MX's geared rotor): 63
    // rad/s, 0.06 x 1 ms; a 5 ms timestep would already be refused.
    let model = builtin("drosophibot2").unwrap();
    assert!(PhysicsRobot::new(&model, &Ground::Flat).is_ok());
    let mut options = PhysicsRobot::options(&model, &Ground::Flat).unwrap();
    options.timestep_s = 0.005;
    assert!(matches!(
        Plant::new(&model, &options),
        Err(PhysicsError::Timestep { .. })
    ));
}

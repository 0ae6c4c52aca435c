//! Robots opened by port name (`physics::open`, as `dbot --port` and `dbot.Board.open` open them):
//! the link says which kind each is, only the physics robot has a body, and the scenes of
//! `physics[:SCENE]` ports.

use std::time::Duration;

use physics::RobotLink;

#[test]
fn board_commands_work_on_every_physics_scene_and_a_bad_scene_is_named() {
    for port in [
        "physics",
        "physics:flat",
        "physics:incline:10",
        "physics:ball",
        "physics:ball-fixed",
    ] {
        let mut b = physics::open(port).unwrap_or_else(|e| panic!("{port}: {e}"));
        assert_eq!(
            b.port(),
            if port == "physics" {
                "physics:flat"
            } else {
                port
            }
        );
        assert!(matches!(b.transport(), RobotLink::Physics(_)), "{port}");
        b.set_telemetry(0).unwrap();
        assert_eq!(b.gaits().unwrap().len(), usize::from(board::robot::SLOTS));
        b.emergency_stop().unwrap();
        b.clear_fault().unwrap();
        b.wait(Duration::from_millis(100)).unwrap();
        let body = b.transport().body().expect("the physics robot has a body");
        // Simulated time is the link's clock.
        assert!(
            (body.time_s - b.now().as_secs_f64()).abs() < 0.011,
            "{port}"
        );
        assert_eq!(body.feet.len(), 6);
    }
    let e = physics::open("physics:moon").unwrap_err().to_string();
    assert!(e.contains("physics:moon") && e.contains("moon"), "{e}");
}

#[test]
fn the_virtual_robot_opens_as_virtual_and_has_no_body() {
    let b = physics::open("virtual").unwrap();
    assert!(matches!(b.transport(), RobotLink::Virtual(_)));
    assert_eq!(b.transport().kind(), "virtual");
    assert!(b.transport().body().is_none());
}

#[test]
fn a_missing_serial_device_is_named() {
    let e = physics::open("/dev/no-such-board").unwrap_err().to_string();
    assert!(e.contains("/dev/no-such-board"), "{e}");
}

/// `physics:...+model:FILE` runs the body of a model file (e.g. one `dbot identify` fitted):
/// its servo dynamics in every joint, its feet's friction over the substrate's ESTIMATE, the
/// file named in the port; the built-in body on the same scene keeps the defaults; a file that
/// does not load is named with its problem.
#[test]
fn a_physics_port_with_a_model_file_runs_that_files_body() {
    use planner::model::{ServoParamsEntry, builtin, to_toml_string};
    let dir = tempfile::tempdir().unwrap();
    let mut m = builtin("drosophibot2").unwrap();
    m.foot_friction = Some(0.8);
    let fitted = ServoParamsEntry {
        p_gain_divisor: Some(160.0),
        damping_nm_s_per_rad: Some(0.02),
        friction_nm: Some(0.03),
        deadband_rad: Some(2.0 * physics::servo::RAD_PER_TICK),
        ..Default::default()
    };
    m.servo_dynamics
        .per_joint
        .push(("LF_CTr".to_owned(), fitted));
    let file = dir.path().join("fitted.toml");
    std::fs::write(&file, to_toml_string(&m, "test", &|_| String::new())).unwrap();
    let port = format!("physics:flat+floor+model:{}", file.display());

    let b = physics::open(&port).unwrap_or_else(|e| panic!("{port}: {e}"));
    assert_eq!(b.port(), port);
    let body = b.transport().physics().expect("a physics robot");
    let lf_ctr = m.joint_index("LF_CTr").unwrap();
    for j in body.plant().joints() {
        let want = m.servo_params(j.joint).unwrap();
        assert_eq!(j.params, want, "{}", j.name);
        if j.joint == lf_ctr {
            assert_eq!(j.params.p_gain_divisor, 160.0);
            assert_eq!(j.params.friction_nm, 0.03);
        }
    }
    for leg in planner::model::Leg::ALL {
        // The model's 0.8, not the floor's ESTIMATE 0.5.
        assert_eq!(body.plant().foot_friction(leg), Some(0.8), "{leg:?}");
    }

    let plain = physics::open("physics:flat+floor").unwrap();
    let plain = plain.transport().physics().unwrap();
    let j = plain
        .plant()
        .joints()
        .iter()
        .find(|j| j.joint == lf_ctr)
        .unwrap();
    assert_eq!(j.params.friction_nm, 0.0);
    assert_eq!(
        plain.plant().foot_friction(planner::model::Leg::LF),
        Some(physics::substrate::FLOOR_MU)
    );

    let missing = dir.path().join("none.toml");
    let e = physics::open(&format!("physics+model:{}", missing.display()))
        .unwrap_err()
        .to_string();
    assert!(e.contains("none.toml") && e.contains("model file"), "{e}");
}

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

//! `physics[:SCENE]` ports through the host's port parser, as `dbot --port` opens them, and the
//! scenes they name.

use std::time::Duration;

use board::link::Board;
use board::port::PortSpec;

#[test]
fn board_commands_work_on_every_physics_scene_and_a_bad_scene_is_named() {
    physics::register_port();
    for port in [
        "physics",
        "physics:flat",
        "physics:incline:10",
        "physics:ball",
        "physics:ball-fixed",
    ] {
        let t = PortSpec::parse(port)
            .open()
            .unwrap_or_else(|e| panic!("{port}: {e}"));
        let mut b = Board::connect(t).unwrap();
        assert_eq!(
            b.port(),
            if port == "physics" {
                "physics:flat"
            } else {
                port
            }
        );
        b.set_telemetry(0).unwrap();
        assert_eq!(b.gaits().unwrap().len(), usize::from(board::robot::SLOTS));
        b.emergency_stop().unwrap();
        b.clear_fault().unwrap();
        b.wait(Duration::from_millis(100)).unwrap();
    }
    let e = PortSpec::parse("physics:moon")
        .open()
        .unwrap_err()
        .to_string();
    assert!(e.contains("physics:moon") && e.contains("moon"), "{e}");
}

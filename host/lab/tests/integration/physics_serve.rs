//! `lab::physics_serve`: a spec that is no physics robot is refused naming it; the robot and its
//! strain board are linked where asked, said in one line, and serving ends when asked to.

use std::sync::atomic::{AtomicBool, Ordering};

use lab::physics_serve::{PhysicsServer, StrainLink};

static STOP: AtomicBool = AtomicBool::new(false);

#[test]
fn a_port_that_is_no_physics_robot_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let e = PhysicsServer::open("virtual", &dir.path().join("board"), None).unwrap_err();
    assert_eq!(
        e.chain_text(),
        "port `virtual` is not a physics robot; give `physics` or `physics:SCENE[+SUBSTRATE][+platform:LEG][+model:FILE]`"
    );
    assert!(!dir.path().join("board").exists());
}

#[test]
fn the_board_and_its_strain_board_are_linked_where_asked_and_stop_when_asked() {
    let dir = tempfile::tempdir().unwrap();
    let (board, strain) = (dir.path().join("board"), dir.path().join("strain"));
    let server = PhysicsServer::open(
        "physics",
        &board,
        Some(StrainLink {
            link: strain.clone(),
            gain: 2.5,
        }),
    )
    .unwrap();
    // Both links point at pseudo-terminals (/dev/pts/N) named in the line.
    for link in [&board, &strain] {
        let target = std::fs::read_link(link).unwrap();
        assert!(target.starts_with("/dev/pts"), "{}", target.display());
        assert!(server.describe().contains(&target.display().to_string()));
    }
    assert!(server.describe().contains("(2.5 counts per microstrain)"));
    assert!(
        server
            .describe()
            .starts_with("serving the physics robot (physics) on /dev/pts/")
    );
    STOP.store(true, Ordering::Relaxed);
    let served = server.serve(&STOP).unwrap();
    assert_eq!(served.strain_error, None);
}

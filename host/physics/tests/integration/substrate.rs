//! A scene's substrate (`TERRAIN+SUBSTRATE`) sets the feet's friction, and an unknown one is
//! refused at the port, naming it and listing the known ones.

use board::port::PortSpec;
use physics::{PhysicsRobot, Substrate, open};
use planner::model::Leg;

#[test]
fn the_scene_substrate_sets_every_foot_friction() {
    for (scene, substrate, mu) in [
        ("flat", Substrate::Sandpaper, 1.5),
        ("flat+floor", Substrate::Floor, 0.5),
        ("incline:10+wire-mesh", Substrate::WireMesh, 0.7),
        ("flat+anti-slip-mat", Substrate::AntiSlipMat, 1.1),
    ] {
        // The port's one parser splits the scene into its ground and substrate.
        let port = format!("physics:{scene}");
        let PortSpec::Physics {
            scene: ground,
            substrate: parsed,
            ..
        } = PortSpec::parse(&port).unwrap()
        else {
            panic!("{port} is not a physics port");
        };
        assert_eq!(parsed, substrate, "{scene}");
        let r = PhysicsRobot::drosophibot_on(&ground, parsed).unwrap();
        assert_eq!(r.substrate(), substrate, "{scene}");
        for leg in [Leg::LF, Leg::LM, Leg::LH, Leg::RF, Leg::RM, Leg::RH] {
            assert_eq!(r.plant().foot_friction(leg), Some(mu), "{scene} {leg:?}");
        }
    }
}

#[test]
fn an_unknown_substrate_is_refused_at_the_port() {
    let e = open("physics:flat+ice").unwrap_err().to_string();
    assert!(
        e.contains("physics:flat+ice")
            && e.contains(
                "unknown substrate `ice` (known: floor, sandpaper, wire-mesh, anti-slip-mat)"
            ),
        "{e}"
    );
}

//! The ground's sliding friction from a walking trial (`lab::identify::friction`): the stand-in
//! robot walks one step of the servo-safe plan on a ground of known friction, and the
//! identification, started from the default friction (1.5, sand paper's ESTIMATE), recovers it
//! when the feet slip, or says it cannot when they do not.

use lab::identify::stand_in;
use lab::identify::{Identification, IdentifyOptions, identify};

/// The stand-in (its servo dynamics, feet of friction `mu`) walking one step of the servo-safe
/// plan of the default model on flat ground, every servo joint recorded, then identified from
/// its servo dynamics (what the suspended trials give,
/// `identify::the_stand_in_is_identified_from_a_suspended_excitation`) and the default's friction.
fn identify_walk_on(mu: f64) -> Identification {
    let default = planner::model::builtin("drosophibot2").unwrap();
    let mut truth = stand_in::stand_in_model(&default);
    truth.foot_friction = Some(mu);
    let walk = crate::identify::stand_in_walk(&default, &truth);
    let start = stand_in::stand_in_model(&default);
    assert_eq!(start.foot_friction, None);
    let id = identify(&[walk], &start, &IdentifyOptions::default()).unwrap();
    eprintln!("{}", lab::identify::report::markdown(&id));
    eprintln!("{:?}", id.friction.as_ref().unwrap());
    id
}

#[test]
fn the_ground_friction_is_identified_from_a_walk_on_a_slippery_floor() {
    let truth = physics::substrate::FLOOR_MU;
    let id = identify_walk_on(truth);
    let fitted = id.model.foot_friction.expect("identified");
    assert!(
        (fitted - truth).abs() <= 0.05 * truth,
        "fitted {fitted}, truth {truth}"
    );
    let e = id.estimate("ground", "foot_friction").unwrap();
    assert_eq!((e.start, e.value), (1.5, fitted));
    assert!(e.sd.is_some() && e.why.is_none(), "{e:?}");
    assert!(
        id.not_identified
            .iter()
            .any(|(f, _)| *f == "servo dynamics")
    );
    let (b, a) = (
        id.before[0].position_rms_rad(),
        id.after[0].position_rms_rad(),
    );
    assert!(a * 3.0 < b, "position RMS before {b}, after {a}");
    // The fitted model file carries it, and reads back through the model's validation.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("fitted.toml");
    let printed = lab::identify::write_outputs(&id, &out).unwrap();
    assert!(
        printed.contains("ground friction (foot_friction): 0.50"),
        "{printed}"
    );
    let back = planner::model::load(&out).unwrap();
    assert_eq!(back.foot_friction, Some(fitted));
}

#[test]
fn a_walk_whose_feet_do_not_slip_leaves_the_friction_unidentified() {
    let truth = physics::substrate::ANTI_SLIP_MAT_MU;
    let id = identify_walk_on(truth);
    assert_eq!(id.model.foot_friction, None);
    let e = id.estimate("ground", "foot_friction").unwrap();
    assert!(
        e.sd.is_none() && e.why.as_deref().unwrap().contains("slip"),
        "{e:?}"
    );
    assert!(id.not_identified.iter().any(|(f, _)| *f == "foot_friction"));
    // What it does say holds: the friction is above about the estimate.
    assert!(e.value <= truth, "{e:?}");
}

//! Identification on the stand-in robot (`lab::identify::stand_in`): a physics robot whose servo
//! dynamics differ from the default in every field records a short suspended excitation, and
//! the identification started from the default model must recover each parameter within the
//! issue's bounds (10 % for gains, damping, friction and the load's gain and offset; one servo
//! tick for backlash and deadband) or name it as not identified.

use lab::identify::stand_in::{self, BUS_PERIOD_S};
use lab::identify::{IdentifyOptions, identify, recording::Recording};
use planner::excitation::{ExcitationKind, ExcitationOptions, excitation};
use planner::model::Model;

/// A short suspended excitation: 0.3 s holds, a 3.5 s chirp.
fn short() -> ExcitationOptions {
    ExcitationOptions {
        hold_s: 0.3,
        chirp_s: 3.5,
        chirp_taper_s: 0.3,
        ..ExcitationOptions::default()
    }
}

/// The stand-in's recording of joints played from suspended tables at once, each `(joint,
/// table kind)`: the suspended legs move independently, so one recording stands for the
/// tables played one after the other (and costs one replay instead of several).
fn stand_in_recording(default: &Model, joints: &[(&str, &str)]) -> Recording {
    let truth = stand_in::stand_in_model(default);
    let ex = excitation(default, ExcitationKind::Suspended, &short()).unwrap();
    let table = |kind: &str| {
        ex.trials
            .iter()
            .find(|t| t.name == format!("sus-{kind}"))
            .unwrap()
    };
    let cycles = joints
        .iter()
        .map(|(_, k)| (table(k).period_s() / BUS_PERIOD_S) as usize)
        .min()
        .unwrap();
    let mut index = Vec::new();
    let mut goals = Vec::new();
    for (name, kind) in joints {
        let j = default.joint_index(name).unwrap();
        let t = table(kind);
        index.push(j);
        goals.extend(stand_in::goals(default, &t.q, t.dt_s, &[j], cycles));
    }
    stand_in::record(&truth, "sus-composite", true, &index, goals).unwrap()
}

/// The default model with the stand-in's I and D gain registers, as a lab reads them from its
/// servos (they are given, not fitted: `lab::identify::params::NOT_FROM_MOTION`).
fn start_model(default: &Model) -> Model {
    let mut m = default.clone();
    for servo in [protocol::ServoModel::Mx28, protocol::ServoModel::Mx64] {
        let truth = stand_in::stand_in_entry(servo);
        let mut e = m.servo_dynamics.of_model(servo).copied().unwrap_or_default();
        e.i_gain = truth.i_gain;
        e.d_gain = truth.d_gain;
        m.servo_dynamics.set_model(servo, e);
    }
    m
}

#[test]
fn the_stand_in_is_identified_from_a_suspended_excitation() {
    let default = planner::model::builtin("drosophibot2").unwrap();
    let t0 = std::time::Instant::now();
    let rec = stand_in_recording(&default, &[("LF_CTr", "CTr"), ("LM_FTi", "FTi")]);
    eprintln!("recorded {} cycles in {:?}", rec.len(), t0.elapsed());
    let t0 = std::time::Instant::now();
    let id = identify(&[rec], &start_model(&default), &IdentifyOptions::default()).unwrap();
    eprintln!("identified in {:?}, {} replays, {}", t0.elapsed(), id.replays, id.termination);
    eprintln!("{}", lab::identify::report::markdown(&id));
}

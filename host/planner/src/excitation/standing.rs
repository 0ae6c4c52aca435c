//! The standing excitation: the robot on its feet shifts its thorax slowly, one displacement after
//! another (heave, surge, sway, roll, pitch, yaw: each out to +A, through -A and back, as
//! `A sin(2 pi t / T)` over its time T), the feet held where they rest by each leg's inverse
//! kinematics. The joints change posture under the body's weight.

use std::f64::consts::PI;

use nalgebra::{UnitQuaternion, Vector3};

use super::{ExcitationError, ExcitationKind, ExcitationOptions, ExcitationTrial, Motion, Segment};
use super::{all_stance, rest, slices_for};
use crate::kinematics::{IkOptions, LegChain};
use crate::model::Model;

/// The thorax displacements in turn: name, translation (m) and rotation (rad, roll-pitch-yaw)
/// per unit of excursion.
fn displacements(o: &ExcitationOptions) -> [(&'static str, f64, Vector3<f64>, Vector3<f64>); 6] {
    let (z, x, y) = (Vector3::z(), Vector3::x(), Vector3::y());
    let none = Vector3::zeros();
    [
        ("heave", o.heave_m, z, none),
        ("surge", o.shift_m, x, none),
        ("sway", o.shift_m, y, none),
        ("roll", o.tilt_rad, none, x),
        ("pitch", o.tilt_rad, none, y),
        ("yaw", o.tilt_rad, none, z),
    ]
}

/// The standing excitation of `model`: one trial.
pub fn standing(
    model: &Model,
    options: &ExcitationOptions,
) -> Result<ExcitationTrial, ExcitationError> {
    let name = "stand";
    let kin = |source| ExcitationError::Kinematics {
        trial: name.into(),
        source,
    };
    let posture = rest(model).map_err(kin)?;
    if model.actuated_joints().is_empty() {
        return Err(ExcitationError::NoJoints {
            model: model.name.clone(),
        });
    }
    let o = options;
    let moves = displacements(o);
    let span = o.posture_s + o.hold_s;
    let total = o.hold_s + span * moves.len() as f64;
    let n = slices_for(total, o.standing_dt_s);
    // The thorax's pose (translation, rotation) relative to its resting pose at each slice.
    let pose = |t: f64| {
        let k = ((t - o.hold_s) / span).floor();
        let local = t - o.hold_s - k * span;
        if k < 0.0 || k as usize >= moves.len() || local > o.posture_s {
            return (Vector3::zeros(), UnitQuaternion::identity());
        }
        let (_, a, dx, dr) = moves[k as usize];
        let s = a * (2.0 * PI * local / o.posture_s).sin();
        let r = dr * s;
        (dx * s, UnitQuaternion::from_euler_angles(r.x, r.y, r.z))
    };
    let times: Vec<f64> = (0..n).map(|s| s as f64 * o.standing_dt_s).collect();
    let mut q = vec![posture.q.clone(); n];
    for (leg, foot) in &posture.feet {
        let chain = LegChain::new(model, *leg).map_err(kin)?;
        let rest_a: Vec<f64> = chain.actuated.iter().map(|&j| posture.q[j]).collect();
        // A foot fixed on the ground seen from the moved thorax: R^T (foot - d).
        let targets: Vec<Vector3<f64>> = times
            .iter()
            .map(|&t| {
                let (d, r) = pose(t);
                r.inverse() * (foot - d)
            })
            .collect();
        let sol = chain
            .solve_path(&targets, &rest_a, &rest_a, &IkOptions::default())
            .map_err(kin)?;
        for (s, qa) in sol.iter().enumerate() {
            for (k, &j) in chain.actuated.iter().enumerate() {
                q[s][j] = qa[k];
            }
        }
    }
    let segments = moves
        .iter()
        .enumerate()
        .map(|(k, &(what, amplitude, _, _))| {
            let start_s = o.hold_s + k as f64 * span;
            Segment {
                joint: "all".into(),
                start_s,
                end_s: start_s + o.posture_s,
                motion: Motion::Posture { what, amplitude },
            }
        })
        .collect();
    Ok(ExcitationTrial {
        name: name.into(),
        kind: ExcitationKind::Standing,
        dt_s: o.standing_dt_s,
        stance: vec![all_stance(model); n],
        q,
        segments,
    })
}

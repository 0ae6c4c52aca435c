//! The suspended excitation: feet in the air, one table per joint kind moving that joint on every
//! leg at once (the leg's other joints hold the resting posture). Each joint: a transfer from the
//! resting posture to its excitation centre, a hold, four steps (+A, back, -A, back) each held,
//! a linear chirp, a hold and the transfer back.

use super::signal::{Chirp, Ramp};
use super::{ExcitationError, ExcitationOptions, ExcitationTrial, Motion, Segment};
use super::{ExcitationKind, rest, sample, slices_for};
use crate::model::{JointKind, Model};

/// A joint's next ramp from its index and its last ramp: (from, to, speed), rad and rad/s.
type RampEnds<'a> = dyn Fn(usize, Option<&Ramp>) -> (f64, f64, f64) + 'a;

/// One excited joint's plan.
struct Joint {
    index: usize,
    rest: f64,
    centre: f64,
    step: f64,
    speed: f64,
    chirp: f64,
}

/// The fastest an excitation moves joint `j`, rad/s: the options' fraction of the lower of its
/// servo's no-load speed in the model and on the datasheet (the rule the board checks with).
pub fn speed_limit(model: &Model, j: usize, options: &ExcitationOptions) -> Option<f64> {
    let p = model.servo_params(j)?;
    let servo = model.joints[j].servo.map(|s| s.model)?;
    let datasheet = f64::from(servo.no_load_speed_rad_s());
    Some(options.speed_fraction * p.no_load_speed_rad_s.min(datasheet))
}

/// The suspended excitation of `model`: one trial per joint kind with servo-driven joints.
pub fn suspended(
    model: &Model,
    options: &ExcitationOptions,
) -> Result<Vec<ExcitationTrial>, ExcitationError> {
    let posture = rest(model).map_err(|source| ExcitationError::Kinematics {
        trial: "suspended".into(),
        source,
    })?;
    let mut kinds: Vec<JointKind> = Vec::new();
    for (j, joint) in model.joints.iter().enumerate() {
        if model.servo_params(j).is_some() && !kinds.contains(&joint.kind) {
            kinds.push(joint.kind);
        }
    }
    if kinds.is_empty() {
        return Err(ExcitationError::NoJoints {
            model: model.name.clone(),
        });
    }
    kinds
        .into_iter()
        .map(|kind| {
            let joints = model
                .joints
                .iter()
                .enumerate()
                .filter(|(j, joint)| joint.kind == kind && model.servo_params(*j).is_some())
                .map(|(j, _)| plan_joint(model, j, posture.q[j], options))
                .collect::<Result<Vec<_>, _>>()?;
            Ok(trial(model, kind, &posture.q, &joints, options))
        })
        .collect()
}

/// Step size, chirp amplitude and centre of joint `j` resting at `rest`.
fn plan_joint(
    model: &Model,
    j: usize,
    rest: f64,
    o: &ExcitationOptions,
) -> Result<Joint, ExcitationError> {
    let joint = &model.joints[j];
    let (lo, hi) = joint.limits;
    let half = 0.5 * (hi - lo) - o.limit_margin_rad;
    if half <= 0.0 {
        return Err(ExcitationError::Range {
            joint: joint.name.clone(),
            lo,
            hi,
            margin: o.limit_margin_rad,
        });
    }
    let speed = speed_limit(model, j, o).expect("only servo joints are excited");
    let step = o.step_rad.min(half);
    let chirp = o
        .chirp_amplitude_rad
        .min(Chirp::amplitude_for_speed(
            speed,
            o.chirp_f1_hz,
            o.chirp_taper_s,
        ))
        .min(half);
    let reach = step.max(chirp);
    let centre = rest.clamp(
        lo + o.limit_margin_rad + reach,
        hi - o.limit_margin_rad - reach,
    );
    Ok(Joint {
        index: j,
        rest,
        centre,
        step,
        speed,
        chirp,
    })
}

/// The table moving `joints` (all of `kind`) from the resting posture `rest_q`.
fn trial(
    model: &Model,
    kind: JointKind,
    rest_q: &[f64],
    joints: &[Joint],
    o: &ExcitationOptions,
) -> ExcitationTrial {
    // The schedule is common to the joints: each span lasts as long as its slowest joint needs.
    let transfer = joints
        .iter()
        .map(|j| (j.centre - j.rest).abs() / o.transfer_speed)
        .fold(0.0, f64::max);
    let step_time = joints.iter().map(|j| j.step / j.speed).fold(0.0, f64::max);
    let chirp_cycles = (0.5 * (o.chirp_f0_hz + o.chirp_f1_hz) * o.chirp_s)
        .round()
        .max(1.0);
    let chirp_s = chirp_cycles / (0.5 * (o.chirp_f0_hz + o.chirp_f1_hz));
    let mut t = 0.0;
    let mut spans: Vec<(usize, f64, f64, Motion)> = Vec::new();
    let mut ramps: Vec<Vec<Ramp>> = vec![Vec::new(); joints.len()];
    let mut chirps: Vec<Option<Chirp>> = vec![None; joints.len()];
    // Each joint's next ramp (from, to, speed) starting at `start`, its span `span_s` long.
    let push_ramps = |ramps: &mut Vec<Vec<Ramp>>,
                      spans: &mut Vec<(usize, f64, f64, Motion)>,
                      start: f64,
                      span_s: f64,
                      ends: &RampEnds| {
        for (k, joint_ramps) in ramps.iter_mut().enumerate() {
            let (from, to, speed) = ends(k, joint_ramps.last());
            let r = Ramp {
                from,
                to,
                start_s: start,
                speed,
            };
            joint_ramps.push(r);
            spans.push((k, start, start + span_s, ramp_motion(&r)));
        }
    };
    // Transfer to the centre, hold.
    push_ramps(&mut ramps, &mut spans, t, transfer, &|k, _| {
        (joints[k].rest, joints[k].centre, o.transfer_speed)
    });
    t += transfer + o.hold_s;
    // Steps: up, back, down, back; each held.
    for offset in [1.0, 0.0, -1.0, 0.0] {
        push_ramps(
            &mut ramps,
            &mut spans,
            t,
            step_time + o.hold_s,
            &|k, last| {
                let j = &joints[k];
                let from = last.map_or(j.centre, |r| r.to);
                (from, j.centre + offset * j.step, j.speed)
            },
        );
        t += step_time + o.hold_s;
    }
    // The chirp, then a hold.
    for (k, j) in joints.iter().enumerate() {
        let c = Chirp {
            centre: j.centre,
            amplitude_rad: j.chirp,
            f0_hz: o.chirp_f0_hz,
            f1_hz: o.chirp_f1_hz,
            start_s: t,
            duration_s: chirp_s,
            taper_s: o.chirp_taper_s,
        };
        chirps[k] = Some(c);
        spans.push((
            k,
            t,
            t + chirp_s,
            Motion::Chirp {
                centre: c.centre,
                amplitude_rad: c.amplitude_rad,
                f0_hz: c.f0_hz,
                f1_hz: c.f1_hz,
                taper_s: c.taper_s,
            },
        ));
    }
    t += chirp_s + o.hold_s;
    // Back to the resting posture, and a last hold before the table loops.
    push_ramps(&mut ramps, &mut spans, t, transfer, &|k, _| {
        (joints[k].centre, joints[k].rest, o.transfer_speed)
    });
    t += transfer + 0.5 * o.hold_s;
    let n = slices_for(t, o.suspended_dt_s);
    let chirp_window = chirps
        .iter()
        .flatten()
        .next()
        .map(|c| (c.start_s, c.start_s + c.duration_s));
    let q = sample(n, o.suspended_dt_s, |time| {
        let mut q = rest_q.to_vec();
        for (k, j) in joints.iter().enumerate() {
            q[j.index] = match (chirps[k], chirp_window) {
                (Some(c), Some((a, b))) if (a..=b).contains(&time) => c.at(time),
                // The latest move begun by now (the chirp ends at the centre, where the
                // last step left the joint).
                _ => ramps[k]
                    .iter()
                    .rev()
                    .find(|r| r.start_s <= time)
                    .map_or(j.rest, |r| r.at(time)),
            };
        }
        q
    });
    let segments = spans
        .into_iter()
        .map(|(k, start_s, end_s, motion)| Segment {
            joint: model.joints[joints[k].index].name.clone(),
            start_s,
            end_s,
            motion,
        })
        .collect();
    ExcitationTrial {
        name: format!("sus-{}", kind.name()),
        kind: ExcitationKind::Suspended,
        dt_s: o.suspended_dt_s,
        stance: vec![0; q.len()],
        q,
        segments,
    }
}

fn ramp_motion(r: &Ramp) -> Motion {
    Motion::Ramp {
        from: r.from,
        to: r.to,
        speed: r.speed,
    }
}

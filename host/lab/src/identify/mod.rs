//! Identification of the servo dynamics (docs/identification.md): the recorded goals of
//! suspended excitation trials replayed on the physics robot's body ([`rollout`]) and the
//! model's servo parameters fitted per joint to the recorded present position and velocity
//! ([`fit`]: Levenberg-Marquardt, bounds, a block-diagonal finite-difference Jacobian; then
//! [`refine`]: Nelder-Mead on each joint's block from where it ended), then the Present Load
//! reading per joint from the load ([`load`]). Every estimate carries a standard deviation from
//! the Jacobian at the point kept (`sigma^2 (J^T J)^-1`, its joint's block); a
//! parameter no reading responds to, or whose block is singular, is named as not identified,
//! with the reason, as are the fields never fitted from motion ([`params::NOT_FROM_MOTION`]).
//!
//! The trials that walked (not suspended) then give the ground's sliding friction
//! ([`friction`]: a scan and a Levenberg-Marquardt refinement of `foot_friction`, the servo
//! dynamics held as fitted), or say that the feet did not slip enough to identify it.
//!
//! `dbot identify` and Python's `dbot.identify` call [`identify_trials`]; [`stand_in`] is the
//! robot with known parameters the procedure is checked on.

pub mod fit;
pub mod friction;
pub mod load;
pub mod params;
pub mod recording;
pub mod refine;
pub mod report;
pub mod rollout;
pub mod stand_in;
pub mod trial_write;

pub use report::{prepare_out, write_outputs};

use nalgebra_lm::DMatrix;
use planner::model::Model;

use crate::bail;
use crate::error::Result;
use crate::replay::{Replay, figures};
use params::{MOTION, NOT_FROM_MOTION};
use recording::Recording;

/// What the gear damping's estimate means (beside its standard deviation, which assumes
/// white residuals and is optimistic here).
pub const DAMPING_NOTE: &str = "identified as part of the joint's viscous total (gear damping + the \
    torque-speed slope + the D gain's Kd), which the fit recovers; alone it is a few % of that total \
    and its own error can be several times its sd (the stand-in's short excitation: up to 21 %; \
    from the full-length tables with 600 refinement replays per joint, within 7 %)";

/// What the stall torque's and the P gain divisor's estimates mean.
pub const STALL_NOTE: &str = "the stiffness (stall torque over divisor) is identified; the stall \
    torque itself only through the I and D gains' scale (no saturation in the excitation), weakly: \
    the fit can end along the valley of equal stiffness (the stand-in's one-leg run: 2 of 5 joints \
    23 to 25 % high with their stiffness within 2 %, 7.5 and 15.5 % after the refinement), with an \
    error many times its sd: the optimisers stop short of the truth's lower cost, and a trial's \
    lowest cost can lie off the truth (on the one-leg run's sus-FTi, 25 % high). From the \
    full-length tables (1 s holds, 20 s chirps) with 600 refinement replays per joint, every stall \
    torque and divisor of that run came within 5 % (docs/identification.md)";

/// What the Coulomb friction's and the deadband's estimates mean.
pub const FRICTION_NOTE: &str = "identified together with the deadband, the gear damping and the \
    stiffness, which make up for one another along a shallow valley: on the stand-in's one-leg run \
    LF_TrF1's friction ended 14.5 % low (deadband 13 % high, gear damping 26 % high) at a cost only \
    2.9 above the truth's 55.0, where the cost is uneven by up to 1.5 between points 5 % apart at \
    the tick scale; moved alone by as much, the friction or the deadband raises the cost to about \
    101. From the full-length tables (1 s holds, 20 s chirps) with 600 refinement replays per \
    joint, every joint's friction came within 6 % (docs/identification.md)";

/// How long the fit may run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IdentifyOptions {
    /// Replays the motion fit may run per recording (each Jacobian costs one replay of every
    /// recording per fitted parameter, so the fit's iterations do not depend on how many trials
    /// are given).
    pub max_replays_per_recording: usize,
    /// Replays the Nelder-Mead refinement after it may run per identified joint ([`refine`]; 0,
    /// the default: none). Off by default: it lowers every joint's cost, but on short trials
    /// the lower cost can lie further from the truth (docs/identification.md).
    pub refine_replays_per_joint: usize,
}

impl Default for IdentifyOptions {
    fn default() -> Self {
        Self {
            max_replays_per_recording: 200,
            refine_replays_per_joint: 0,
        }
    }
}

/// One parameter of one joint: where the fit started, where it ended, its standard deviation
/// (`None`: not identified, `why` says why).
#[derive(Debug, Clone, PartialEq)]
pub struct Estimate {
    pub joint: String,
    pub field: &'static str,
    pub unit: &'static str,
    pub start: f64,
    pub value: f64,
    pub sd: Option<f64>,
    pub why: Option<String>,
}

/// What an identification found.
#[derive(Debug, Clone)]
pub struct Identification {
    /// The fitted model: the input with every identified joint's fitted fields as its overrides.
    pub model: Model,
    pub estimates: Vec<Estimate>,
    /// Fields not fitted for any joint, and why.
    pub not_identified: Vec<(&'static str, String)>,
    /// Each recording replayed before (the input model) and after (the fitted one).
    pub before: Vec<Replay>,
    pub after: Vec<Replay>,
    /// Joints no trial identified, given the median of their servo model's identified joints.
    pub generalised: Vec<String>,
    /// Replays run, and how the optimiser ended.
    pub replays: usize,
    pub termination: String,
    /// What the refinement after Levenberg-Marquardt did, per identified joint (empty when
    /// none ran).
    pub refinement: Vec<refine::JointRefinement>,
    /// The ground friction's fit, when a trial walked.
    pub friction: Option<friction::FrictionFit>,
}

impl Identification {
    /// The estimate of `field` for `joint`.
    pub fn estimate(&self, joint: &str, field: &str) -> Option<&Estimate> {
        self.estimates
            .iter()
            .find(|e| e.joint == joint && e.field == field)
    }
}

/// Identifies `model`'s servo dynamics from the trial folders `dirs` (see the module's header).
pub fn identify_trials(
    dirs: &[std::path::PathBuf],
    model: &Model,
    options: &IdentifyOptions,
) -> Result<Identification> {
    let recs = dirs
        .iter()
        .map(|d| Recording::read(d, model))
        .collect::<Result<Vec<_>>>()?;
    identify(&recs, model, options)
}

/// Why the servo dynamics are not fitted when no trial hung.
pub const NO_SUSPENDED: &str = "no suspended trial given: the servo dynamics are fitted from the \
    suspended excitation (`dbot excite --kind suspended`, tables named sus-*), played with the feet \
    in the air; kept as the model gives them";

/// Identifies `model` from `recordings` (see the header): the servo dynamics from the suspended
/// ones, then the ground friction from those that walked, on the fitted servo dynamics.
pub fn identify(
    recordings: &[Recording],
    model: &Model,
    options: &IdentifyOptions,
) -> Result<Identification> {
    if recordings.is_empty() {
        bail!("no trial given: identification needs suspended excitation trials or walking trials");
    }
    let (suspended, walks): (Vec<Recording>, Vec<Recording>) =
        recordings.iter().cloned().partition(|r| r.suspended);
    let mut id = if suspended.is_empty() {
        Identification {
            model: model.clone(),
            estimates: Vec::new(),
            not_identified: vec![("servo dynamics", NO_SUSPENDED.to_owned())],
            before: Vec::new(),
            after: Vec::new(),
            generalised: Vec::new(),
            replays: 0,
            termination: "no servo fit (no suspended trial)".to_owned(),
            refinement: Vec::new(),
            friction: None,
        }
    } else {
        identify_servos(&suspended, model, options)?
    };
    if suspended.is_empty() {
        id.model.name = format!("{}-identified", model.name);
    }
    if walks.is_empty() {
        return Ok(id);
    }
    let before = walks
        .iter()
        .map(|r| crate::replay::replay_recording(model, r))
        .collect::<Result<Vec<_>>>()?;
    let f = friction::fit(&id.model, &walks)?;
    id.estimates.push(Estimate {
        joint: "ground".to_owned(),
        field: "foot_friction",
        unit: "",
        start: f.start,
        value: f.value,
        sd: f.sd,
        why: f.why.clone(),
    });
    match &f.why {
        None => id.model.foot_friction = Some(f.value),
        Some(why) => id.not_identified.push(("foot_friction", why.clone())),
    }
    id.replays += f.replays + 2 * walks.len();
    let after = walks
        .iter()
        .map(|r| crate::replay::replay_recording(&id.model, r))
        .collect::<Result<Vec<_>>>()?;
    id.before.extend(before);
    id.after.extend(after);
    id.friction = Some(f);
    Ok(id)
}

/// The servo dynamics from the suspended recordings `suspended` (not empty).
fn identify_servos(
    suspended: &[Recording],
    model: &Model,
    options: &IdentifyOptions,
) -> Result<Identification> {
    let mut joints: Vec<usize> = Vec::new();
    for r in suspended {
        for jt in &r.joints {
            if !joints.contains(&jt.joint) {
                joints.push(jt.joint);
            }
        }
    }
    let before = suspended
        .iter()
        .map(|r| crate::replay::replay_recording(model, r))
        .collect::<Result<Vec<_>>>()?;

    let budget = options.max_replays_per_recording * suspended.len();
    let problem = fit::MotionFit::new(model, suspended, joints.clone(), budget);
    let (problem, report) = levenberg_marquardt::LevenbergMarquardt::new()
        .with_patience(100)
        .with_ftol(1e-3)
        .with_xtol(1e-3)
        .minimize(problem);
    if let Some(e) = problem.error.borrow_mut().take() {
        return Err(e);
    }
    let best = problem
        .best
        .as_ref()
        .map_or_else(|| problem.x().clone(), |(_, x)| x.clone());
    let termination = format!("{:?}", report.termination);
    let (best, refinement) = if options.refine_replays_per_joint > 0 {
        refine::refine(&problem, &best, options.refine_replays_per_joint)?
    } else {
        (best, Vec::new())
    };
    // The standard deviations: the Jacobian at the point kept (after the refinement).
    let mut at_best = fit::MotionFit::new(model, suspended, joints.clone(), usize::MAX);
    levenberg_marquardt::LeastSquaresProblem::set_params(&mut at_best, &best);
    let jac = at_best.jacobian_now()?;
    let cost = levenberg_marquardt::LeastSquaresProblem::residuals(&at_best)
        .map_or(0.0, |r| r.norm_squared());
    let replays = problem.replays.get()
        + at_best.replays.get()
        + refinement.iter().map(|r| r.replays).sum::<usize>();
    let mut fitted = problem.model_at(&best);

    let mut estimates = Vec::new();
    let dof = (jac.nrows() as f64 - jac.ncols() as f64).max(1.0);
    let sigma2 = cost / dof;
    let np = MOTION.len();
    for (k, &j) in joints.iter().enumerate() {
        let block = jac.columns(k * np, np).into_owned();
        let start = model.servo_params(j).expect("a servo joint");
        let end = fitted.servo_params(j).expect("a servo joint");
        let sds = block_sd(&block, sigma2);
        for (i, f) in MOTION.iter().enumerate() {
            let (sd, why) = match sds[i] {
                _ if block.column(i).norm() < 1e-9 => (
                    None,
                    Some("no recorded reading changes when it changes: the trials do not excite it".to_owned()),
                ),
                None => (
                    None,
                    Some("its effect on the readings is a combination of the others' (the joint's information matrix is singular)".to_owned()),
                ),
                Some(sd) if f.name == "damping_nm_s_per_rad" => (Some(sd * f.scale), Some(DAMPING_NOTE.to_owned())),
                Some(sd) if f.name == "stall_torque_nm" || f.name == "p_gain_divisor" => {
                    (Some(sd * f.scale), Some(STALL_NOTE.to_owned()))
                }
                Some(sd) if f.name == "friction_nm" || f.name == "deadband_rad" => {
                    (Some(sd * f.scale), Some(FRICTION_NOTE.to_owned()))
                }
                Some(sd) => (Some(sd * f.scale), None),
            };
            estimates.push(Estimate {
                joint: model.joints[j].name.clone(),
                field: f.name,
                unit: f.unit,
                start: (f.get)(&start),
                value: (f.get)(&end),
                sd,
                why,
            });
        }
    }

    // The Present Load reading, per joint, against the fitted motion's torque.
    let mut load_fits = Vec::new();
    for r in suspended {
        let out = rollout::replay(&fitted, r)?;
        for (k, jt) in r.joints.iter().enumerate() {
            let map = fitted.joints[jt.joint].servo.expect("a servo joint");
            let rec: Vec<f64> = jt
                .load_raw
                .iter()
                .map(|&x| crate::replay::recorded_nm(&fitted, jt.joint, x))
                .collect();
            let unit = f64::from(dynamixel::units::load_to_torque_nm(map.model, 1));
            let Some(l) = load::fit(&rec, &out.torque[k], &jt.load_raw, unit) else {
                continue;
            };
            load_fits.push((jt.joint, f64::from(map.sign), l));
        }
    }
    for (j, sign, l) in load_fits {
        let name = fitted.joints[j].name.clone();
        let start = model.servo_params(j).expect("a servo joint");
        let mut e = fit::entry_of(&fitted, j);
        e.load_gain = Some(l.gain);
        e.load_offset_nm = Some(sign * l.offset_nm);
        e.load_resolution_counts = Some(l.resolution_counts);
        e.load_noise_nm = Some(l.noise_nm);
        fitted.servo_dynamics.set_joint(&name, e);
        for (field, unit, s, v, sd) in [
            ("load_gain", "", start.load_gain, l.gain, Some(l.gain_sd)),
            (
                "load_offset_nm",
                "N m",
                start.load_offset_nm,
                sign * l.offset_nm,
                Some(l.offset_sd),
            ),
            (
                "load_resolution_counts",
                "counts",
                f64::from(start.load_resolution_counts),
                f64::from(l.resolution_counts),
                None,
            ),
            (
                "load_noise_nm",
                "N m",
                start.load_noise_nm,
                l.noise_nm,
                None,
            ),
        ] {
            estimates.push(Estimate {
                joint: name.clone(),
                field,
                unit,
                start: s,
                value: v,
                sd,
                why: None,
            });
        }
    }
    let generalised = generalise(&mut fitted, &joints);
    fitted.name = format!("{}-identified", model.name);
    let after = suspended
        .iter()
        .map(|r| rollout::replay(&fitted, r).map(|out| figures(&fitted, r, &out)))
        .collect::<Result<Vec<_>>>()?;
    let mut not_identified: Vec<(&'static str, String)> = NOT_FROM_MOTION
        .iter()
        .map(|(f, why)| (*f, (*why).to_owned()))
        .collect();
    not_identified.push((
        "armature_kg_m2 (with the body's inertia)",
        "the armature adds to the segment's inertia seen by the joint; it is fitted, but its \
         share is only as good as the model's segment inertias"
            .to_owned(),
    ));
    Ok(Identification {
        model: fitted,
        estimates,
        not_identified,
        before,
        after,
        generalised,
        replays,
        termination,
        refinement,
        friction: None,
    })
}

/// Standard deviations (scaled units) of one joint's parameters from its Jacobian block and the
/// residual variance: `sqrt(diag(sigma^2 (J^T J)^-1))`, `None` where the information matrix is
/// singular in that parameter.
fn block_sd(block: &DMatrix<f64>, sigma2: f64) -> Vec<Option<f64>> {
    let info = block.transpose() * block;
    let n = info.nrows();
    match info.clone().try_inverse() {
        Some(inv) => (0..n)
            .map(|i| {
                let v = inv[(i, i)] * sigma2;
                (v.is_finite() && v >= 0.0 && info[(i, i)] > 1e-12).then(|| v.sqrt())
            })
            .collect(),
        None => vec![None; n],
    }
}

/// Gives every servo joint of `model` not in `identified` the median, field by field, of the
/// identified joints with its servo model (as its own overrides); returns those joints' names.
fn generalise(model: &mut Model, identified: &[usize]) -> Vec<String> {
    let mut out = Vec::new();
    for j in 0..model.joints.len() {
        if identified.contains(&j) {
            continue;
        }
        let Some(servo) = model.joints[j].servo.map(|s| s.model) else {
            continue;
        };
        if model.servo_params(j).is_none() {
            continue;
        }
        let peers: Vec<planner::model::ServoParamsEntry> = identified
            .iter()
            .filter(|&&i| model.joints[i].servo.map(|s| s.model) == Some(servo))
            .map(|&i| fit::entry_of(model, i))
            .collect();
        if peers.is_empty() {
            continue;
        }
        let median = |f: &dyn Fn(&planner::model::ServoParamsEntry) -> Option<f64>| {
            let mut v: Vec<f64> = peers.iter().filter_map(f).collect();
            v.sort_by(f64::total_cmp);
            (!v.is_empty()).then(|| v[v.len() / 2])
        };
        let mut e = fit::entry_of(model, j);
        for f in MOTION {
            if let Some(v) = median(&|p| {
                let mut probe = planner::model::ServoParams::defaults(servo);
                probe = probe.with(p);
                p.given()
                    .iter()
                    .any(|(n, _)| *n == f.name)
                    .then(|| (f.get)(&probe))
            }) {
                (f.set)(&mut e, v);
            }
        }
        e.load_gain = median(&|p| p.load_gain).or(e.load_gain);
        e.load_offset_nm = median(&|p| p.load_offset_nm).or(e.load_offset_nm);
        e.load_noise_nm = median(&|p| p.load_noise_nm).or(e.load_noise_nm);
        e.load_resolution_counts = median(&|p| p.load_resolution_counts.map(f64::from))
            .map(|v| v as u16)
            .or(e.load_resolution_counts);
        let name = model.joints[j].name.clone();
        model.servo_dynamics.set_joint(&name, e);
        out.push(name);
    }
    out
}

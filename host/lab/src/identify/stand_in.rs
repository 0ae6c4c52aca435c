//! The stand-in robot: a physics robot whose model file differs from the default in every servo
//! dynamics parameter (softer, damped, with friction, backlash, deadband, a Present Load gain of
//! 0.8 with an offset, a coarser and noisy load), and what its servos would report when it plays
//! a table: the identification's ground truth (docs/identification.md).
//!
//! Its recordings are made on the body the identification replays on ([`super::rollout`]), at
//! the bus rate, with the servo's own quantisation: goals and positions in whole ticks, velocity
//! in the register's 0.229 rev/min, load through the model's Present Load reading (its gain,
//! offset, resolution and seeded noise, `physics::servo::present_load`).

use planner::model::{Model, ServoParamsEntry};

use super::recording::{JointTrace, Recording, StrainTrace};
use super::rollout;
use crate::error::Result;

/// The bus period the stand-in records at, s (the board's default 100 Hz).
pub const BUS_PERIOD_S: f64 = 0.01;
/// Seed of the Present Load noise.
pub const NOISE_SEED: u64 = 37;

/// The stand-in's servo dynamics, the same for both servo models, every field away from its
/// default (`planner::model::ServoParams::defaults`): the P gain divisor 160 (a 20 % softer
/// servo than the e-manual's 128), I 30 and D 120 registers, gear damping 0.02 N m s/rad and
/// friction 0.03 N m, armature 1.3x, a deadband of 2 ticks and a backlash of 3 ticks, the
/// torque-speed line at 0.9x stall and 0.9x no-load speed, and the load read at gain 0.8 with
/// a 0.05 N m offset, in steps of 2 counts with 0.01 N m of noise.
pub fn stand_in_entry(servo: protocol::ServoModel) -> ServoParamsEntry {
    let d = planner::model::ServoParams::defaults(servo);
    let tick = physics::servo::RAD_PER_TICK;
    ServoParamsEntry {
        p_gain_divisor: Some(160.0),
        i_gain: Some(30),
        d_gain: Some(120),
        damping_nm_s_per_rad: Some(0.02),
        friction_nm: Some(0.03),
        armature_kg_m2: Some(1.3 * d.armature_kg_m2),
        deadband_rad: Some(2.0 * tick),
        backlash_rad: Some(3.0 * tick),
        stall_torque_nm: Some(0.9 * d.stall_torque_nm),
        no_load_speed_rad_s: Some(0.9 * d.no_load_speed_rad_s),
        load_gain: Some(0.8),
        load_offset_nm: Some(0.05),
        load_resolution_counts: Some(2),
        load_noise_nm: Some(0.01),
    }
}

/// `model` with the stand-in's servo dynamics for every servo model it uses (joint overrides
/// removed).
pub fn stand_in_model(model: &Model) -> Model {
    let mut m = model.clone();
    m.servo_dynamics.per_joint.clear();
    for servo in [protocol::ServoModel::Mx28, protocol::ServoModel::Mx64] {
        m.servo_dynamics.set_model(servo, stand_in_entry(servo));
    }
    m.name = format!("{}-stand-in", model.name);
    m
}

/// `model` (its servo dynamics as they are) with the stand-in's Present Load reading on both
/// servo models: gain 0.8, offset 0.05 N m, steps of 2 counts, 0.01 N m of noise. The body
/// moves as `model`'s; only what the servos report differs (the calibration's ground truth).
pub fn reading_stand_in_model(model: &Model) -> Model {
    let mut m = with_reading_of(model, &stand_in_model(model));
    m.name = format!("{}-reading-stand-in", model.name);
    m
}

/// `model` with `reading`'s Present Load reading (gain, offset, resolution, noise) on both servo
/// models, its servo dynamics otherwise as they are: e.g. the full stand-in's body read as the
/// default model reads it (what identification gives a lab before any calibration).
pub fn with_reading_of(model: &Model, reading: &Model) -> Model {
    let mut m = model.clone();
    for servo in [protocol::ServoModel::Mx28, protocol::ServoModel::Mx64] {
        let r = reading
            .servo_dynamics
            .of_model(servo)
            .copied()
            .unwrap_or_default();
        let mut e = m
            .servo_dynamics
            .of_model(servo)
            .copied()
            .unwrap_or_default();
        e.load_gain = r.load_gain;
        e.load_offset_nm = r.load_offset_nm;
        e.load_resolution_counts = r.load_resolution_counts;
        e.load_noise_nm = r.load_noise_nm;
        m.servo_dynamics.set_model(servo, e);
    }
    m
}

/// The goals of a table of slices `q[slice][model joint]` `dt` s apart at the bus rate, linear
/// between slices as the board interpolates, in whole ticks, for `joints` (model indices), over
/// `cycles` bus cycles (from the start of the table, wrapping).
pub fn goals(
    model: &Model,
    q: &[Vec<f64>],
    dt: f64,
    joints: &[usize],
    cycles: usize,
) -> Vec<Vec<f64>> {
    let n = q.len();
    joints
        .iter()
        .map(|&j| {
            (0..cycles)
                .map(|c| {
                    let s = c as f64 * BUS_PERIOD_S / dt;
                    let k = s.floor() as usize;
                    let f = s - s.floor();
                    let a = q[k % n][j];
                    let b = q[(k + 1) % n][j];
                    quantise(model, j, a + f * (b - a))
                })
                .collect()
        })
        .collect()
}

/// Angle `q` of joint `j` to the nearest whole servo tick.
fn quantise(model: &Model, j: usize, q: f64) -> f64 {
    let map = model.joints[j].servo.expect("a servo joint");
    let tick = std::f64::consts::TAU / f64::from(map.model.ticks_per_rev());
    map.zero_offset + ((q - map.zero_offset) / tick).round() * tick
}

/// What the stand-in (`model`, already the stand-in's) records playing `goals` (per joint of
/// `joints`, per bus cycle): the readings its servos report, quantised as they quantise.
pub fn record(
    model: &Model,
    name: &str,
    suspended: bool,
    joints: &[usize],
    goals: Vec<Vec<f64>>,
) -> Result<Recording> {
    record_with_strain(model, name, suspended, joints, goals, None)
}

/// The stand-in's gain of the strain board's column `column`, counts per microstrain: 0.3 +
/// 0.02 x column (0.3 to 1.0 over the 36 columns), every one away from the virtual board's
/// default 0.5 but column 10's.
pub fn gauge_gain(column: usize) -> f64 {
    0.3 + 0.02 * column as f64
}

/// [`record`], and with `gauge_gains` (per strain board column, counts per microstrain) the
/// strain board beside it: every [`physics::STRAIN_SAMPLE_S`] the model's simulated gauges as
/// counts, 300 + gain x microstrain rounded to a whole count and held in 0..1023 (the virtual
/// board's ADC, `board::strain::virtual_board`), its baseline the first sample.
pub fn record_with_strain(
    model: &Model,
    name: &str,
    suspended: bool,
    joints: &[usize],
    goals: Vec<Vec<f64>>,
    gauge_gains: Option<&[f64]>,
) -> Result<Recording> {
    let cycles = goals.first().map_or(0, Vec::len);
    let mut rec = Recording {
        name: name.to_owned(),
        suspended,
        t: (0..cycles).map(|c| c as f64 * BUS_PERIOD_S).collect(),
        strain: None,
        joints: joints
            .iter()
            .zip(goals)
            .map(|(&j, goal)| JointTrace {
                name: model.joints[j].name.clone(),
                joint: j,
                q: vec![goal[0]],
                goal,
                qd: Vec::new(),
                load_raw: Vec::new(),
            })
            .collect(),
    };
    let out = rollout::replay_gauges(model, &rec, gauge_gains.is_some())?;
    if let Some(gains) = gauge_gains {
        rec.strain = Some(strain_counts(model, &rec.t, &out.strain, gains));
    }
    let mut rng = NOISE_SEED;
    let velocity_unit = f64::from(dynamixel::units::RAD_S_PER_VELOCITY_UNIT);
    for (k, jt) in rec.joints.iter_mut().enumerate() {
        let map = model.joints[jt.joint].servo.expect("a servo joint");
        let params = model.servo_params(jt.joint).expect("a servo joint");
        let sign = f64::from(map.sign);
        jt.q = out.q[k]
            .iter()
            .map(|&q| quantise(model, jt.joint, q))
            .collect();
        jt.qd = out.qd[k]
            .iter()
            .map(|&v| (v / velocity_unit).round() * velocity_unit)
            .collect();
        jt.load_raw = out.torque[k]
            .iter()
            .map(|&tau| {
                let normal = standard_normal(&mut rng);
                physics::servo::present_load(map.model, &params, sign * tau, normal)
            })
            .collect();
    }
    Ok(rec)
}

/// The strain board's record of `strain[cycle][model gauge]` at cycle times `t`: a sample each
/// time [`physics::STRAIN_SAMPLE_S`] has passed, counts through `gains` per column.
fn strain_counts(model: &Model, t: &[f64], strain: &[Vec<f64>], gains: &[f64]) -> StrainTrace {
    use board::strain::virtual_board::BASELINE;
    let names = board::strain::channels::names();
    let gauge_of: Vec<Option<usize>> = names
        .iter()
        .map(|n| model.gauges.iter().position(|g| &g.name == n))
        .collect();
    let mut trace = StrainTrace {
        names,
        ..StrainTrace::default()
    };
    let mut next = 0.0;
    for (c, &tc) in t.iter().enumerate() {
        if tc + 1e-9 < next {
            continue;
        }
        next = tc + physics::STRAIN_SAMPLE_S;
        let row = gauge_of
            .iter()
            .zip(gains)
            .map(|(g, gain)| {
                let e = g.map_or(0.0, |g| strain[c][g]);
                (BASELINE + gain * e)
                    .round()
                    .clamp(0.0, board::strain::line::MAX_COUNT)
            })
            .collect();
        trace.t.push(tc);
        trace.counts.push(row);
    }
    trace.baseline = trace.counts.first().cloned().unwrap_or_default();
    trace.baseline_first_sample = true;
    trace
}

/// `truth` records the standing excitation (`options`) of `default` with every servo joint and
/// the strain board beside it (gains [`gauge_gain`]), as the trial folder `out/stand`.
pub fn write_standing_trial(
    truth: &Model,
    default: &Model,
    options: &planner::excitation::ExcitationOptions,
    out: &std::path::Path,
) -> Result<std::path::PathBuf> {
    let rec = record_standing(truth, default, options)?;
    super::trial_write::write_trial(&rec, default, out)
}

/// What `truth` records playing the standing excitation (`options`) of `default` with every
/// servo joint, the strain board beside it (gains [`gauge_gain`]).
pub fn record_standing(
    truth: &Model,
    default: &Model,
    options: &planner::excitation::ExcitationOptions,
) -> Result<Recording> {
    use planner::excitation::{ExcitationKind, excitation};
    let ex = excitation(default, ExcitationKind::Standing, options)
        .map_err(|e| crate::LabError::invalid(format!("the standing excitation: {e}")))?;
    let table = &ex.trials[0];
    let all: Vec<usize> = (0..default.joints.len())
        .filter(|&j| default.servo_params(j).is_some())
        .collect();
    let cycles = (table.period_s() / BUS_PERIOD_S) as usize;
    let gains: Vec<f64> = (0..board::strain::channels::CHANNELS)
        .map(gauge_gain)
        .collect();
    record_with_strain(
        truth,
        &table.name,
        false,
        &all,
        goals(default, &table.q, table.dt_s, &all, cycles),
        Some(&gains),
    )
}

/// A standard normal sample (Box-Muller on two uniforms of `planner::terrain::splitmix64`).
fn standard_normal(state: &mut u64) -> f64 {
    let mut uniform = || {
        *state = planner::terrain::splitmix64(*state);
        ((*state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    let (u1, u2) = (uniform(), uniform());
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// The stand-in's trial folders ([`write_trials`]).
#[derive(Debug, Clone, PartialEq)]
pub struct StandInTrials {
    /// One per suspended excitation table that moves a chosen joint.
    pub suspended: Vec<std::path::PathBuf>,
    /// One step of the servo-safe walk on flat ground, every servo joint: held out.
    pub walk: std::path::PathBuf,
}

/// The stand-in of `default` records, as trial folders under `out`: the suspended excitation
/// (`options`) of the joints named in `joints` (every servo joint when empty), one trial per
/// table, and a held-out step of the servo-safe walk.
pub fn write_trials(
    default: &Model,
    options: &planner::excitation::ExcitationOptions,
    joints: &[String],
    out: &std::path::Path,
) -> Result<StandInTrials> {
    use planner::excitation::{ExcitationKind, excitation};
    let truth = stand_in_model(default);
    for name in joints {
        if default
            .joint_index(name)
            .and_then(|j| default.servo_params(j))
            .is_none()
        {
            crate::bail!(
                "stand-in: `{name}` is not a servo joint of the model {}",
                default.name
            );
        }
    }
    let ex = excitation(default, ExcitationKind::Suspended, options)
        .map_err(|e| crate::LabError::invalid(format!("the suspended excitation: {e}")))?;
    let mut suspended = Vec::new();
    for table in &ex.trials {
        let moved: Vec<usize> = table
            .segments
            .iter()
            .filter_map(|s| default.joint_index(&s.joint))
            .filter(|&j| joints.is_empty() || joints.contains(&default.joints[j].name))
            .fold(Vec::new(), |mut v, j| {
                if !v.contains(&j) {
                    v.push(j);
                }
                v
            });
        if moved.is_empty() {
            continue;
        }
        let cycles = (table.period_s() / BUS_PERIOD_S) as usize;
        let goals = goals(default, &table.q, table.dt_s, &moved, cycles);
        let rec = record(&truth, &table.name, true, &moved, goals)?;
        suspended.push(super::trial_write::write_trial(&rec, default, out)?);
    }
    let params =
        planner::gait::StepParams::preset("servo-safe", &default.name).ok_or_else(|| {
            crate::LabError::invalid(format!("no servo-safe preset for {}", default.name))
        })?;
    let plan = planner::plan::plan(default, &params)?;
    let all: Vec<usize> = (0..default.joints.len())
        .filter(|&j| default.servo_params(j).is_some())
        .collect();
    let cycles = (plan.period_s / BUS_PERIOD_S) as usize;
    let walk = record(
        &truth,
        "walk",
        false,
        &all,
        goals(default, &plan.q, plan.dt, &all, cycles),
    )?;
    let walk = super::trial_write::write_trial(&walk, default, out)?;
    Ok(StandInTrials { suspended, walk })
}

/// The model a lab identifying the stand-in starts from: `default` with the I and D gain
/// registers read from the stand-in's servos (registers are given, not fitted:
/// [`super::params::NOT_FROM_MOTION`]).
pub fn start_model(default: &Model) -> Model {
    let mut m = default.clone();
    for servo in [protocol::ServoModel::Mx28, protocol::ServoModel::Mx64] {
        let read = stand_in_entry(servo);
        let mut e = m
            .servo_dynamics
            .of_model(servo)
            .copied()
            .unwrap_or_default();
        (e.i_gain, e.d_gain) = (read.i_gain, read.d_gain);
        m.servo_dynamics.set_model(servo, e);
    }
    m
}

//! Replaying a recording's goals on the physics robot's body ([`physics::Plant`]: MuJoCo and the
//! servos' control law of the model's servo dynamics), bus cycle by bus cycle: at each recorded
//! cycle the body's state is read as the servo would report it, then the goals sent in that
//! cycle are held until the next. A suspended recording hangs the body in the air (the
//! thorax fixed 0.1 m above where it would stand); any other stands on flat ground.
//!
//! The replay holds the recording's first goals for [`PRE_ROLL_S`] first, while gravity ramps in
//! ([`physics::GRAVITY_RAMP_S`]): a recorded trial starts with the robot already held and
//! settled. Where it starts depends on what determines the body's state:
//! - **suspended**: in the recording's first posture. A hung leg carries only its own
//!   segments, so its posture gives its state.
//! - **standing**: in the first *goals*, the body settling into the recorded posture as gravity
//!   ramps in, as the robot did when it took its weight. Six planted feet share the weight in a
//!   way no posture fixes: on servos with friction, deadband and backlash it depends on how the
//!   body took it (where each servo rests in its deadband). Started in the recorded (sagged)
//!   posture, the servos would first lift the body towards their goals and share it otherwise.
//!   Measured on the stand-in, the held-out walk's replay on its own model: 2.79 mrad RMS from
//!   the recorded posture, 0.44 from the goals (docs/identification.md).

use physics::Plant;
use planner::model::{MjcfOptions, Model, to_mjcf};
use planner::terrain::Ground;

use super::recording::Recording;
use crate::error::{Context, Result};

/// How long the first goals are held before the recording's first cycle, s.
pub const PRE_ROLL_S: f64 = 1.2;
/// Height the suspended body hangs above its standing place, m.
pub const SUSPEND_RAISE_M: f64 = 0.1;

/// What the replay gives per recorded joint and cycle: angle (rad), velocity (rad/s) and the
/// actuator's torque on the joint (N m, joint direction); and, when the recording has strain,
/// per cycle every gauge of the model as the physics robot simulates it
/// (`physics::SimulatedGauges`, microstrain, `model.gauges` order).
#[derive(Debug, Clone, PartialEq)]
pub struct Replayed {
    pub q: Vec<Vec<f64>>,
    pub qd: Vec<Vec<f64>>,
    pub torque: Vec<Vec<f64>>,
    /// `strain[cycle][gauge]`, empty when not simulated.
    pub strain: Vec<Vec<f64>>,
}

/// The MJCF of `model` in `options`, hung in the air when `suspended`: no free joint, the thorax
/// raised [`SUSPEND_RAISE_M`] (its keyframe without the free joint's 7 coordinates).
pub fn mjcf(model: &Model, options: &MjcfOptions, suspended: bool) -> String {
    let xml = to_mjcf(model, options);
    if !suspended {
        return xml;
    }
    let mut out = String::with_capacity(xml.len());
    let body = format!(r#"    <body name="{}" pos=""#, model.bodies[0].name);
    for line in xml.lines() {
        if line.trim() == r#"<freejoint name="root"/>"# {
            continue;
        }
        if let Some(rest) = line.strip_prefix(&body) {
            let (pos, tail) = rest.split_once('"').expect("the body line closes its pos");
            let mut p: Vec<f64> = pos.split(' ').filter_map(|v| v.parse().ok()).collect();
            p[2] += SUSPEND_RAISE_M;
            out.push_str(&format!("{body}{:e} {:e} {:e}\"{tail}\n", p[0], p[1], p[2]));
            continue;
        }
        if let Some((head, rest)) = line.split_once(r#"<key name="stance" qpos=""#) {
            let (qpos, tail) = rest.split_once('"').expect("the key closes its qpos");
            let kept: Vec<&str> = qpos.split(' ').skip(7).collect();
            out.push_str(&format!(
                "{head}<key name=\"stance\" qpos=\"{}\"{tail}\n",
                kept.join(" ")
            ));
            continue;
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}

/// The plant of `model` for `rec`: in its first posture if suspended, else in its first goals
/// (the joints it does not trace in the stance; see the module's header), every servo holding
/// its first goal, with the gains the board's registers give.
pub fn plant(model: &Model, rec: &Recording) -> Result<(Plant, Vec<usize>)> {
    let mut options = MjcfOptions::stance(model, &Ground::Flat)
        .with_context(|| format!("the stance of the model {}", model.name))?;
    options.timestep_s = physics::TIMESTEP_S;
    for jt in &rec.joints {
        options.stance_q[jt.joint] = if rec.suspended { jt.q[0] } else { jt.goal[0] };
    }
    let xml = mjcf(model, &options, rec.suspended);
    let mut plant = Plant::from_mjcf(model, &options, &xml)
        .with_context(|| format!("loading the model {} into MuJoCo", model.name))?;
    let mut index = Vec::with_capacity(rec.joints.len());
    for jt in &rec.joints {
        let i = plant
            .joints()
            .iter()
            .position(|p| p.joint == jt.joint)
            .expect("every traced joint has a servo (Recording checks)");
        index.push(i);
    }
    for i in 0..plant.joints().len() {
        let p = &plant.joints()[i];
        let (kp, ki, kd) = gains(model, p.joint, &p.params);
        let goal = options.stance_q[p.joint];
        plant.set_kp(i, kp);
        plant.set_ki_kd(i, ki, kd);
        plant.set_goal(i, goal, true);
    }
    for (jt, &i) in rec.joints.iter().zip(&index) {
        plant.set_goal(i, jt.goal[0], true);
    }
    Ok((plant, index))
}

/// The P, I and D gains (N m/rad, N m/(rad s), N m s/rad) the physics robot gives joint `j`: its
/// stiffness as the firmware writes it to the P gain register, and the model's I and D
/// registers, through the model's servo dynamics (`physics::servo::gains_of_registers`).
pub fn gains(model: &Model, j: usize, params: &planner::model::ServoParams) -> (f64, f64, f64) {
    let map = model.joints[j]
        .servo
        .expect("a servo joint has a servo map");
    let stiffness = match model.joints[j].actuation {
        planner::model::Actuation::Actuated { stiffness, .. } => stiffness,
        planner::model::Actuation::Fixed { .. } => 0.0,
    };
    let p = physics::servo::p_gain_for_stiffness(map.model, stiffness);
    physics::servo::gains_of_registers(map.model, params, p, params.i_gain, params.d_gain)
}

/// Replays `rec`'s goals on `model`'s body (see the module's header), simulating the gauges
/// when `rec` recorded strain.
pub fn replay(model: &Model, rec: &Recording) -> Result<Replayed> {
    replay_gauges(model, rec, rec.strain.is_some())
}

/// [`replay`], simulating the model's gauges at every cycle when `gauges`.
pub fn replay_gauges(model: &Model, rec: &Recording, gauges: bool) -> Result<Replayed> {
    let (mut plant, index) = plant(model, rec)?;
    let gauges = if gauges && !model.gauges.is_empty() {
        Some(
            physics::SimulatedGauges::new(model, &plant)
                .with_context(|| format!("the gauges of the model {}", model.name))?,
        )
    } else {
        None
    };
    let n = rec.len();
    let k = rec.joints.len();
    let mut out = Replayed {
        q: vec![Vec::with_capacity(n); k],
        qd: vec![Vec::with_capacity(n); k],
        torque: vec![Vec::with_capacity(n); k],
        strain: Vec::new(),
    };
    plant.advance_to(PRE_ROLL_S);
    for c in 0..n {
        for (j, &i) in index.iter().enumerate() {
            let (q, qd, tau) = plant.joint_state(i);
            out.q[j].push(q);
            out.qd[j].push(qd);
            out.torque[j].push(tau);
        }
        if let Some(g) = &gauges {
            out.strain.push(g.read(&plant).microstrain());
        }
        for (jt, &i) in rec.joints.iter().zip(&index) {
            plant.set_goal(i, jt.goal[c], true);
        }
        let next = rec.t.get(c + 1).copied().unwrap_or(rec.t[c] + 0.01);
        plant.advance_to(PRE_ROLL_S + next - rec.t[0]);
    }
    Ok(out)
}

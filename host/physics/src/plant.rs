//! [`Plant`]: a model loaded into MuJoCo with its servos as actuators, stepped at the MJCF's
//! timestep. Each step sets every actuator's control from its servo's goal through the servo's
//! control law ([`crate::drive`]: the model's servo dynamics, [`planner::model::ServoParams`]),
//! and switches a joint's actuator off while its backlash is open.
//!
//! Gravity is ramped in over [`GRAVITY_RAMP_S`] from the moment every servo holds (torque on): a
//! robot is set down on its feet after its servos are switched on; until then it floats, still.
//! Ramping avoids the drop transient of a sudden full weight (host-crates.md).

use mujoco_rs::prelude::*;
use mujoco_rs::wrappers::mj_model::{MjtDisableBit, MjtObjBase};
use planner::model::{
    Actuation, Leg, MjcfOptions, Model, ServoMap, ServoParams, joint_actuator, to_mjcf,
};

use crate::drive::{self, Drive, DriveState, Gains};
use crate::error::PhysicsError;
use crate::timestep::check_timestep;

/// Time over which gravity reaches its full value, s.
pub const GRAVITY_RAMP_S: f64 = 1.0;

/// One actuated joint with its servo.
#[derive(Debug, Clone, PartialEq)]
pub struct PlantJoint {
    /// Index in the model's joints.
    pub joint: usize,
    pub name: String,
    pub map: ServoMap,
    /// Stiffness, N m/rad, and stall torque, N m, of the actuator.
    pub kp: f64,
    pub stall: f64,
    /// Goal angle, rad, and whether the servo holds it.
    pub goal: f64,
    pub torque_on: bool,
    /// Integral and derivative gains, N m/(rad s) and N m s/rad (from the I and D registers).
    pub ki: f64,
    pub kd: f64,
    /// The servo's dynamics in the model ([`Model::servo_params`]).
    pub params: ServoParams,
    /// The torque-speed line's slope in the actuator, N m s/rad.
    kv: f64,
    /// The control law's memory, and the last step's command.
    state: DriveState,
    last: Option<Drive>,
    /// Whether the actuator drives the joint (false while the backlash is open).
    engaged: bool,
    qpos: usize,
    dof: usize,
    actuator: usize,
}

impl PlantJoint {
    /// The control law's gains now.
    fn gains(&self) -> Gains {
        Gains {
            kp: self.kp,
            ki: self.ki,
            kd: self.kd,
            stall: self.stall,
            kv: self.kv,
            deadband: self.params.deadband_rad,
            backlash: self.params.backlash_rad,
        }
    }
}

/// A model in MuJoCo.
pub struct Plant {
    pub(crate) data: MjData<Box<MjModel>>,
    joints: Vec<PlantJoint>,
    /// Each foot's contact sphere (geom id), model feet order.
    pub(crate) feet: Vec<(Leg, usize)>,
    /// The thorax's body id.
    pub(crate) thorax: usize,
    gravity: [f64; 3],
    /// Simulated time at which every servo first held, s.
    held_since: Option<f64>,
    weight_n: f64,
    /// [`Self::step`]'s scratch: each joint's speed before the step (kept to spare an
    /// allocation per MuJoCo step; not state).
    speeds: Vec<f64>,
}

impl std::fmt::Debug for Plant {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Plant")
            .field("time", &self.data.time())
            .field("joints", &self.joints)
            .finish_non_exhaustive()
    }
}

/// The plant's whole simulated state ([`Plant::state`]), to put back with [`Plant::set_state`]:
/// MuJoCo's data in full (`mj_copyData`: state, warm start and every derived quantity), the
/// servos' control-law memory and goals, and the gravity ramp.
#[derive(Clone)]
pub struct PlantState {
    data: MjData<Box<MjModel>>,
    joints: Vec<PlantJoint>,
    held_since: Option<f64>,
    gravity: [f64; 3],
}

impl std::fmt::Debug for PlantState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PlantState")
            .field("time", &self.data.time())
            .finish_non_exhaustive()
    }
}

impl Plant {
    /// Loads `model` as [`to_mjcf`] writes it with `options`, in the stance of the options' keyframe,
    /// servo goals at the stance and torque off.
    pub fn new(model: &Model, options: &MjcfOptions) -> Result<Self, PhysicsError> {
        Self::from_mjcf(model, options, &to_mjcf(model, options))
    }

    /// Loads `xml`, the MJCF of `model` with `options` maybe with more bodies (the perturbation
    /// platform, [`crate::platform::with_platform`]), as [`Self::new`] does.
    pub fn from_mjcf(
        model: &Model,
        options: &MjcfOptions,
        xml: &str,
    ) -> Result<Self, PhysicsError> {
        let mj = MjModel::from_xml_string(xml).map_err(|e| PhysicsError::Load {
            model: model.name.clone(),
            message: e.to_string(),
        })?;
        let mut data = MjData::new(Box::new(mj));
        data.reset_keyframe(0).map_err(|e| PhysicsError::Load {
            model: model.name.clone(),
            message: format!("keyframe `stance`: {e}"),
        })?;
        data.forward();
        check_timestep(model, &data)?;
        let mj = data.model();
        let find = |kind: MjtObjBase, what: &'static str, name: &str| {
            mj.name_to_id(kind, name)
                .ok_or_else(|| PhysicsError::Missing {
                    model: model.name.clone(),
                    kind: what,
                    name: name.to_owned(),
                })
        };
        let mut joints = Vec::new();
        for (j, joint) in model.joints.iter().enumerate() {
            let Actuation::Actuated {
                actuator,
                stiffness,
            } = joint.actuation
            else {
                continue;
            };
            let map = joint.servo.ok_or_else(|| PhysicsError::NoServo {
                model: model.name.clone(),
                joint: joint.name.clone(),
            })?;
            let params = model.servo_params(j).ok_or_else(|| PhysicsError::NoServo {
                model: model.name.clone(),
                joint: joint.name.clone(),
            })?;
            let act = joint_actuator(model, j).expect("an actuated joint has an actuator");
            debug_assert_eq!(actuator.servo(), Some(map.model));
            let jid = find(MjtObjBase::mjOBJ_JOINT, "joint", &joint.name)?;
            let aid = find(MjtObjBase::mjOBJ_ACTUATOR, "actuator", &joint.name)?;
            joints.push(PlantJoint {
                joint: j,
                name: joint.name.clone(),
                map,
                kp: stiffness,
                stall: act.stall_nm,
                goal: options.stance_q[j],
                torque_on: false,
                ki: 0.0,
                kd: 0.0,
                params,
                kv: act.damping,
                state: DriveState::default(),
                last: None,
                engaged: true,
                qpos: mj.jnt_qposadr()[jid] as usize,
                dof: mj.jnt_dofadr()[jid] as usize,
                actuator: aid,
            });
        }
        let mut feet = Vec::new();
        for f in &model.feet {
            let name = format!("{}_foot", f.leg.name());
            feet.push((f.leg, find(MjtObjBase::mjOBJ_GEOM, "foot sphere", &name)?));
        }
        let thorax = find(MjtObjBase::mjOBJ_BODY, "body", &model.bodies[0].name)?;
        let gravity = mj.opt().gravity;
        let g = (gravity[0].powi(2) + gravity[1].powi(2) + gravity[2].powi(2)).sqrt();
        let weight_n = mj.body_subtreemass()[thorax] * g;
        data.model_opt_mut().gravity = [0.0; 3];
        // One robot is one island: island discovery costs about a quarter of a step and changes
        // no result (measured with benches/physics_robot.rs' tuning mode, docs/performance.md).
        data.model_opt_mut().disableflags |= MjtDisableBit::mjDSBL_ISLAND as i32;
        data.forward();
        Ok(Self {
            data,
            joints,
            feet,
            thorax,
            gravity,
            held_since: None,
            weight_n,
            speeds: Vec::new(),
        })
    }

    /// The actuated joints, in the model's joint order.
    pub fn joints(&self) -> &[PlantJoint] {
        &self.joints
    }

    /// Sets a joint's goal (rad) and torque.
    pub fn set_goal(&mut self, i: usize, goal: f64, torque_on: bool) {
        let j = &mut self.joints[i];
        j.goal = goal;
        j.torque_on = torque_on;
    }

    /// Sets joint `i`'s stiffness to `kp` N m/rad (e.g. from its servo's P gain register): the
    /// position actuator's gain and the P controller's saturation both follow.
    pub fn set_kp(&mut self, i: usize, kp: f64) {
        if self.joints[i].kp == kp {
            return;
        }
        self.joints[i].kp = kp;
        if self.joints[i].engaged {
            self.write_actuator(i, kp, self.joints[i].kv);
        }
    }

    /// Sets joint `i`'s integral and derivative gains (from its servo's I and D registers).
    pub fn set_ki_kd(&mut self, i: usize, ki: f64, kd: f64) {
        self.joints[i].ki = ki;
        self.joints[i].kd = kd;
    }

    /// The actuator of joint `i` as `kp ctrl - kp q - kv qdot`.
    fn write_actuator(&mut self, i: usize, kp: f64, kv: f64) {
        let a = self.joints[i].actuator;
        // SAFETY: only the actuator's gain and bias parameters change; every size, index and
        // address stays as it was. A position actuator is kp ctrl - kp q - kv qdot.
        unsafe {
            let m = self.data.model_mut();
            m.actuator_gainprm_mut()[a][0] = kp;
            m.actuator_biasprm_mut()[a][1] = -kp;
            m.actuator_biasprm_mut()[a][2] = -kv;
        }
    }

    /// Engages or parts joint `i`'s gears: apart, its actuator gives no force at all.
    fn set_engaged(&mut self, i: usize, engaged: bool) {
        if self.joints[i].engaged == engaged {
            return;
        }
        self.joints[i].engaged = engaged;
        let (kp, kv) = if engaged {
            (self.joints[i].kp, self.joints[i].kv)
        } else {
            (0.0, 0.0)
        };
        self.write_actuator(i, kp, kv);
    }

    /// The PWM duty joint `i`'s controller outputs at its present angle: the proportional term
    /// past the deadband plus the last step's integral and derivative terms.
    pub fn duty(&self, i: usize) -> f64 {
        let j = &self.joints[i];
        if !j.torque_on {
            return 0.0;
        }
        let q = self.data.qpos()[j.qpos];
        let e = drive::past_deadband(j.goal - q, j.params.deadband_rad);
        let extra = j.last.map_or(0.0, |d| d.extra);
        drive::duty_of(j.kp * e + extra, j.stall)
    }

    /// Cuts (or raises) joint `i`'s stall torque to `stall` N m: the P controller's saturation and
    /// MuJoCo's actuator force limit both follow (e.g. servos too weak for a gait).
    pub fn set_stall(&mut self, i: usize, stall: f64) {
        self.joints[i].stall = stall;
        let a = self.joints[i].actuator;
        // SAFETY: only a force limit changes; every size, index and address stays as it was.
        unsafe { self.data.model_mut() }.actuator_forcerange_mut()[a] = [-stall, stall];
    }

    /// Sets the sliding friction of every contact between a foot and the terrain to `mu` (a
    /// [`crate::substrate`]'s): MuJoCo takes the larger of two geoms' coefficients, so the foot
    /// spheres and every terrain geom (the ground, a ball) all get `mu`.
    pub fn set_friction(&mut self, mu: f64) {
        let feet: Vec<usize> = self.feet.iter().map(|&(_, g)| g).collect();
        // SAFETY: only friction coefficients change; every size, index and address stays as it was.
        let m = unsafe { self.data.model_mut() };
        // The terrain is what the feet collide with (contype 2, see planner::model::to_mjcf).
        let terrain: Vec<usize> = (0..m.geom_contype().len())
            .filter(|&g| m.geom_contype()[g] & 2 != 0)
            .collect();
        for g in feet.into_iter().chain(terrain) {
            m.geom_friction_mut()[g][0] = mu;
        }
    }

    /// The perturbation platform's actuator and its slide's qpos and qvel addresses, if the plant
    /// has one.
    pub(crate) fn platform_slide(&self) -> Option<(usize, usize, usize)> {
        let m = self.data.model();
        let a = m.name_to_id(MjtObjBase::mjOBJ_ACTUATOR, "platform")?;
        let j = m.name_to_id(MjtObjBase::mjOBJ_JOINT, "platform")?;
        Some((a, m.jnt_qposadr()[j] as usize, m.jnt_dofadr()[j] as usize))
    }

    /// Moves the perturbation platform's box (body `platform`) to stand centred at `xy` (world,
    /// m), its slide where it is; nothing without a platform.
    pub(crate) fn place_platform(&mut self, xy: [f64; 2]) {
        let Some(b) = self
            .data
            .model()
            .name_to_id(MjtObjBase::mjOBJ_BODY, "platform")
        else {
            return;
        };
        // SAFETY: only a body's position offset changes; every size, index and address stays.
        let m = unsafe { self.data.model_mut() };
        let z = m.body_pos()[b][2];
        m.body_pos_mut()[b] = [xy[0], xy[1], z];
    }

    /// Joint `name`'s gear train as MuJoCo holds it: the damping (N m s/rad), frictionloss (N m)
    /// and armature (kg m^2) of its degree of freedom (the MJCF's, from the model's servo
    /// dynamics).
    pub fn joint_gear(&self, name: &str) -> Option<(f64, f64, f64)> {
        let j = self.joints.iter().find(|j| j.name == name)?;
        let m = self.data.model();
        Some((
            m.dof_damping()[j.dof],
            m.dof_frictionloss()[j.dof],
            m.dof_armature()[j.dof],
        ))
    }

    /// The sliding friction coefficient of foot `leg`'s sphere.
    pub fn foot_friction(&self, leg: Leg) -> Option<f64> {
        let (_, g) = self.feet.iter().find(|&&(l, _)| l == leg)?;
        Some(self.data.model().geom_friction()[*g][0])
    }

    /// MuJoCo's solver and integrator options (e.g. to compare solver settings in a bench); the
    /// timestep is best changed through the MJCF options, which also place the stance.
    pub fn option_mut(&mut self) -> &mut MjOption {
        self.data.model_opt_mut()
    }

    /// A copy of the whole simulated state (see [`PlantState`]).
    pub fn state(&self) -> PlantState {
        PlantState {
            data: self.data.clone(),
            joints: self.joints.clone(),
            held_since: self.held_since,
            gravity: self.data.model_opt().gravity,
        }
    }

    /// Puts back a state [`Self::state`] took of this plant (or of one built alike); time
    /// included. Panics on a state of another model.
    pub fn set_state(&mut self, state: &PlantState) {
        state
            .data
            .copy_to(&mut self.data)
            .expect("a state of a plant of the same model");
        self.joints.clone_from(&state.joints);
        self.held_since = state.held_since;
        self.data.model_opt_mut().gravity = state.gravity;
    }

    /// Simulated time, s.
    pub fn time(&self) -> f64 {
        self.data.time()
    }

    /// The timestep, s.
    pub fn timestep(&self) -> f64 {
        self.data.model_opt().timestep
    }

    /// One MuJoCo step under the servos' control law.
    pub fn step(&mut self) {
        let t = self.data.time();
        if self.held_since.is_none() && self.joints.iter().all(|j| j.torque_on) {
            self.held_since = Some(t);
        }
        let ramp = self
            .held_since
            .map_or(0.0, |t0| ((t - t0) / GRAVITY_RAMP_S).clamp(0.0, 1.0));
        let gravity = self.gravity.map(|g| g * ramp);
        if self.data.model_opt().gravity != gravity {
            self.data.model_opt_mut().gravity = gravity;
        }
        let h = self.timestep();
        // Three passes over the joints before the step (the drives, MuJoCo's controls, the gears
        // that engage or part) and one after: each joint's drive reads only its own state, so
        // the order changes nothing, and MuJoCo's slices are borrowed once per step.
        let mut speeds = std::mem::take(&mut self.speeds);
        speeds.clear();
        let (qpos, qvel) = (self.data.qpos(), self.data.qvel());
        for j in &mut self.joints {
            let g = j.gains();
            let (q, qd) = (qpos[j.qpos], qvel[j.dof]);
            j.last = Some(drive::drive(q, qd, j.goal, j.torque_on, &g, &j.state, h));
            speeds.push(qd);
        }
        let ctrl = self.data.ctrl_mut();
        for j in &self.joints {
            if let Some(d) = &j.last {
                ctrl[j.actuator] = d.ctrl;
            }
        }
        for i in 0..self.joints.len() {
            if let Some(engaged) = self.joints[i].last.as_ref().map(|d| d.engaged) {
                self.set_engaged(i, engaged);
            }
        }
        self.data.step();
        for (j, &qd) in self.joints.iter_mut().zip(&speeds) {
            let g = j.gains();
            if let Some(d) = &j.last {
                drive::advance(&mut j.state, d, j.torque_on, qd, &g, h);
            }
        }
        self.speeds = speeds;
    }

    /// Steps until simulated time reaches `t_s` (to within half a step).
    pub fn advance_to(&mut self, t_s: f64) {
        let h = self.timestep();
        while self.data.time() + 0.5 * h < t_s {
            self.step();
        }
    }

    /// Angle (rad), velocity (rad/s) and actuator torque (N m) of joint `i`.
    pub fn joint_state(&self, i: usize) -> (f64, f64, f64) {
        let j = &self.joints[i];
        (
            self.data.qpos()[j.qpos],
            self.data.qvel()[j.dof],
            self.data.actuator_force()[j.actuator],
        )
    }

    /// Whether every servo has held long enough for the full weight to be on the feet.
    pub fn full_gravity(&self) -> bool {
        self.held_since
            .is_some_and(|t0| self.data.time() - t0 >= GRAVITY_RAMP_S)
    }

    /// Weight of the robot at full gravity, N.
    pub fn weight_n(&self) -> f64 {
        self.weight_n
    }

    /// Sum of the normal forces of all contacts, N.
    pub fn contact_normal_total(&self) -> f64 {
        (0..self.data.ncon() as usize)
            .map(|i| self.data.contact_force(i)[0])
            .sum()
    }

    /// Contact force on each foot in world coordinates, N (zero for a foot in the air).
    pub fn foot_forces(&self) -> Vec<(Leg, [f64; 3])> {
        let contacts = self.data.contact();
        self.feet
            .iter()
            .map(|&(leg, geom)| {
                let mut f = [0.0; 3];
                for (i, c) in contacts.iter().enumerate() {
                    let sign = if c.geom[0] as usize == geom {
                        -1.0
                    } else if c.geom[1] as usize == geom {
                        1.0
                    } else {
                        continue;
                    };
                    // Contact frame rows: normal (from geom 0 to geom 1), then two tangents.
                    let local = self.data.contact_force(i);
                    for (k, fk) in f.iter_mut().enumerate() {
                        *fk += sign * (0..3).map(|r| local[r] * c.frame[3 * r + k]).sum::<f64>();
                    }
                }
                (leg, f)
            })
            .collect()
    }

    /// World position of each foot sphere's centre, m.
    pub fn foot_positions(&self) -> Vec<(Leg, [f64; 3])> {
        let xpos = self.data.geom_xpos();
        self.feet.iter().map(|&(leg, g)| (leg, xpos[g])).collect()
    }

    /// Thorax position (m) and orientation (quaternion w, x, y, z) in the world.
    pub fn thorax_pose(&self) -> ([f64; 3], [f64; 4]) {
        (
            self.data.xpos()[self.thorax],
            self.data.xquat()[self.thorax],
        )
    }
}

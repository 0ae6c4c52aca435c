//! [`PhysicsRobot`]: a MuJoCo body as the [`ServoDynamics`] of the board's virtual robot (the
//! firmware library's board over the simulated Dynamixel bus, `board::robot::VirtualRobot`).
//! Before each bus cycle the plant steps to the cycle's start (the bus loop's grid point, so the
//! bytes on the bus move nothing in the body: test `bus_traffic`) under the goals the servos hold,
//! and the servos' Present registers take the body's angles, velocities and actuator torques; the
//! firmware's cycle then reads them and writes new goals. Within a cycle's few milliseconds of
//! bus traffic the servos report the state at its start (a real servo samples continuously: up
//! to one cycle of extra latency here). On request it logs every cycle ([`WalkLog`]: gait slice,
//! thorax pose, foot forces, joint angles every N cycles, the gauge samples taken in it) for the
//! demo's comparisons and animation. With the perturbation platform ([`Self::with_platform`])
//! the bus carries one more servo, the platform's, whose Goal Position the slide follows
//! ([`crate::platform`]).

use board::robot::{ServoDynamics, VirtualFlash, VirtualRobot, VirtualTransport};
use dynamixel::control_table as ct;
use dynamixel::sim::VirtualChain;
use dynamixel::sim::physics::MotorState;
use firmware::controller::{Config, Controller};
use planner::model::{Leg, MjcfOptions, Model};
use planner::terrain::Ground;

use crate::error::PhysicsError;
use crate::figures::{Figures, Monitor};
use crate::gauges::{SimulatedStrain, StrainSampler};
use crate::plant::Plant;
use crate::platform::LEVEL_TICKS;
use crate::servo;
use crate::substrate::Substrate;
use crate::walk_log::{WalkLog, WalkSample};

/// The physics robot's MuJoCo timestep, s: 1 ms, twice the MJCF export's default, for speed (the
/// contact's 2 ms time constant is still two steps). Halving it changes the walk's figures by
/// less than the bounds of tests/integration/walk_figures.rs.
pub const TIMESTEP_S: f64 = 0.001;

/// The board's virtual robot with a MuJoCo body moving its servos.
pub type PhysicsBoard = VirtualRobot<PhysicsRobot>;
/// A link to a [`PhysicsBoard`] (the virtual robot's transport).
pub type PhysicsTransport = VirtualTransport<PhysicsRobot>;

/// A simulated body whose joints are the virtual robot's servos.
#[derive(Debug)]
pub struct PhysicsRobot {
    plant: Plant,
    scene: Ground,
    substrate: Substrate,
    monitor: Monitor,
    /// Whether the monitor samples the body every bus cycle ([`Self::set_figures`]).
    figures_on: bool,
    /// The model's joint count (the length of a logged pose).
    model_joints: usize,
    /// The thorax height of the planner's stance (the keyframe), m.
    planned_height_m: f64,
    log: Option<WalkLog>,
    /// The model's gauges, sampled as the strain board samples (`crate::gauges`).
    strain: StrainSampler,
    platform: Option<PlatformRig>,
    /// The generator of the Present Load noise (fixed seed; drawn only for a servo with noise).
    load_rng: std::cell::Cell<u64>,
    /// A settled state to keep, kept, or to skip to ([`Self::keep_state_at`],
    /// [`Self::skip_to_state`]).
    settle: Option<Settle>,
    /// The servos on the bus, `(id, model)`, as the model file maps them.
    servos: Vec<(u8, dynamixel::ServoModel)>,
    /// The model file's `foot_friction` (None: the substrate's ESTIMATE holds).
    foot_friction: Option<f64>,
    /// The model file the body was built from, named in the port (`+model:FILE`).
    model_file: Option<String>,
}

/// What the body does about a stored state at the next bus cycles.
#[derive(Debug)]
enum Settle {
    /// Keep the state of the first cycle at or after this time, s.
    Keep(f64),
    Kept(Box<PhysicsState>),
    /// Stand still (no MuJoCo step) until the first cycle at or after this time, s, then become
    /// this state.
    Skip(f64, Box<PhysicsState>),
}

/// The body's state at a bus cycle's start, as [`PhysicsRobot::keep_state_at`] keeps it and
/// [`PhysicsRobot::skip_to_state`] puts it back: the plant's ([`crate::PlantState`]), the gauges'
/// recent samples, the Present Load noise generator and the figures' monitor.
#[derive(Debug, Clone)]
pub struct PhysicsState {
    plant: crate::plant::PlantState,
    strain: std::collections::VecDeque<SimulatedStrain>,
    load_rng: u64,
    monitor: Monitor,
}

/// Seed of the Present Load noise.
const LOAD_NOISE_SEED: u64 = 0x10AD_5EED;

/// The perturbation platform in the plant and its servo on the bus.
#[derive(Debug, Clone)]
struct PlatformRig {
    /// The platform servo's bus ID.
    servo_id: u8,
    /// The slide's actuator (its control is the top's height, m) and its qpos and qvel
    /// addresses.
    actuator: usize,
    qpos: usize,
    qvel: usize,
    /// The height the servo's profile has reached, m.
    command_m: f64,
    /// The servo's Goal Position this cycle, ticks.
    goal: u32,
    /// The leg under whose foot the box goes when the goal first leaves [`LEVEL_TICKS`]
    /// (`None`: it stays where it was put).
    follow: Option<Leg>,
}

/// Where the perturbation platform's box stands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PlatformPlace {
    /// Centred at this world x, y, m, from the start.
    At([f64; 2]),
    /// Parked 1 m beside the robot until the platform servo's Goal Position first leaves
    /// [`LEVEL_TICKS`] (the firmware's schedule moving it, at the perturbed step's first cycle),
    /// then centred under this leg's foot as it is at that cycle (its top still level with the
    /// ground: the foot lands on it or already stands on it as it rises).
    UnderFootOf(Leg),
}

/// Where [`PlatformPlace::UnderFootOf`] parks the box: 1 m to the robot's left, no foot near.
const PARKED_XY: [f64; 2] = [0.0, 1.0];

impl PhysicsRobot {
    /// Drosophibot II (the built-in model) on `scene`, on sand paper (the paper's substrate).
    pub fn drosophibot(scene: &Ground) -> Result<Self, PhysicsError> {
        Self::drosophibot_on(scene, Substrate::Sandpaper)
    }

    /// Drosophibot II on `scene` and `substrate` (its friction: [`crate::substrate::friction`]).
    pub fn drosophibot_on(scene: &Ground, substrate: Substrate) -> Result<Self, PhysicsError> {
        Ok(Self::new(&drosophibot()?, scene)?.on_substrate(substrate))
    }

    /// The same body on `substrate`: the feet's and the ground's friction become the model
    /// file's `foot_friction` when it gives one (identified on the lab's ground:
    /// docs/identification.md), else the substrate's ([`crate::substrate::friction`], an
    /// ESTIMATE).
    pub fn on_substrate(mut self, substrate: Substrate) -> Self {
        self.plant.set_friction(self.friction_on(substrate));
        self.substrate = substrate;
        self
    }

    /// The feet's sliding friction on `substrate`: the model file's, else the substrate's.
    pub fn friction_on(&self, substrate: Substrate) -> f64 {
        self.foot_friction
            .unwrap_or_else(|| crate::substrate::friction(substrate))
    }

    /// Names the model file the body was built from in its port (`physics:...+model:FILE`), so
    /// a trial's port says which body it ran on.
    pub fn from_model_file(mut self, file: &str) -> Self {
        self.model_file = Some(file.to_owned());
        self
    }

    /// `model` on `scene`, standing in the planner's resting posture, its servos switched off,
    /// stepped at [`TIMESTEP_S`].
    pub fn new(model: &Model, scene: &Ground) -> Result<Self, PhysicsError> {
        Self::with_options(model, &Self::options(model, scene)?, scene)
    }

    /// The MJCF options [`Self::new`] uses: the planner's stance on `scene`, at [`TIMESTEP_S`].
    pub fn options(model: &Model, scene: &Ground) -> Result<MjcfOptions, PhysicsError> {
        let mut options =
            MjcfOptions::stance(model, scene).map_err(|source| PhysicsError::Scene {
                model: model.name.clone(),
                scene: scene.to_string(),
                source,
            })?;
        options.timestep_s = TIMESTEP_S;
        Ok(options)
    }

    /// `model` with explicit MJCF options (e.g. another timestep); `scene` names it, on sand
    /// paper ([`Self::on_substrate`] changes it).
    pub fn with_options(
        model: &Model,
        options: &MjcfOptions,
        scene: &Ground,
    ) -> Result<Self, PhysicsError> {
        let mut plant = Plant::new(model, options)?;
        plant.set_friction(
            model
                .foot_friction
                .unwrap_or_else(|| crate::substrate::friction(Substrate::Sandpaper)),
        );
        let planned_height_m = plant.thorax_pose().0[2];
        let strain = StrainSampler::new(model, &plant)?;
        Ok(Self {
            plant,
            scene: *scene,
            substrate: Substrate::Sandpaper,
            monitor: Monitor::new(),
            figures_on: true,
            model_joints: model.joints.len(),
            planned_height_m,
            log: None,
            strain,
            platform: None,
            load_rng: std::cell::Cell::new(LOAD_NOISE_SEED),
            settle: None,
            servos: model.servo_chain(),
            foot_friction: model.foot_friction,
            model_file: None,
        })
    }

    /// Drosophibot II on `scene` and `substrate` with the perturbation platform at `place`,
    /// moved by a servo at bus ID `servo_id` (beside the joints' servos: no joint's ID) whose
    /// Goal Position the slide follows (see [`crate::platform`]).
    pub fn with_platform(
        scene: &Ground,
        substrate: Substrate,
        servo_id: u8,
        place: PlatformPlace,
    ) -> Result<Self, PhysicsError> {
        Self::of_model_with_platform(&drosophibot()?, scene, substrate, servo_id, place)
    }

    /// [`Self::with_platform`] for the body of `model`.
    pub fn of_model_with_platform(
        model: &Model,
        scene: &Ground,
        substrate: Substrate,
        servo_id: u8,
        place: PlatformPlace,
    ) -> Result<Self, PhysicsError> {
        let (at_xy, follow) = match place {
            PlatformPlace::At(xy) => (xy, None),
            PlatformPlace::UnderFootOf(leg) => (PARKED_XY, Some(leg)),
        };
        let options = Self::options(model, scene)?;
        let plain = Self::with_options(model, &options, scene)?.on_substrate(substrate);
        let xml = crate::platform::with_platform(&planner::model::to_mjcf(model, &options), at_xy);
        let mut plant = Plant::from_mjcf(model, &options, &xml)?;
        plant.set_friction(plain.friction_on(plain.substrate));
        let (actuator, qpos, qvel) =
            plant
                .platform_slide()
                .ok_or_else(|| PhysicsError::Missing {
                    model: model.name.clone(),
                    kind: "slide",
                    name: "platform".into(),
                })?;
        Ok(Self {
            plant,
            platform: Some(PlatformRig {
                servo_id,
                actuator,
                qpos,
                qvel,
                command_m: 0.0,
                goal: u32::from(LEVEL_TICKS),
                follow,
            }),
            ..plain
        })
    }

    /// Keeps the body's state at the first bus cycle starting at or after `t_s` s of simulated
    /// time, right after the plant stepped to it (take it with [`Self::take_kept_state`]).
    pub fn keep_state_at(&mut self, t_s: f64) {
        self.settle = Some(Settle::Keep(t_s));
    }

    /// The state [`Self::keep_state_at`] kept (None: not reached yet, or none asked).
    pub fn take_kept_state(&mut self) -> Option<PhysicsState> {
        match self.settle.take() {
            Some(Settle::Kept(s)) => Some(*s),
            other => {
                self.settle = other;
                None
            }
        }
    }

    /// From now on the body stands still (MuJoCo is not stepped; the servos keep showing the
    /// present state) until the first bus cycle starting at or after `t_s`, where it becomes
    /// `state` instead of stepping: a robot that went through the same requests as the one
    /// that kept `state` at `t_s` then goes on as that one did, without simulating the span
    /// (a reset from a stored settled state). Refused with the perturbation platform, whose
    /// slide the state does not cover.
    pub fn skip_to_state(&mut self, t_s: f64, state: PhysicsState) -> Result<(), PhysicsError> {
        if self.platform.is_some() {
            return Err(PhysicsError::Unsupported {
                what: "skipping to a stored state with the perturbation platform".into(),
            });
        }
        self.settle = Some(Settle::Skip(t_s, Box::new(state)));
        Ok(())
    }

    fn state(&self) -> PhysicsState {
        PhysicsState {
            plant: self.plant.state(),
            strain: self.strain.history.clone(),
            load_rng: self.load_rng.get(),
            monitor: self.monitor.clone(),
        }
    }

    fn set_state(&mut self, s: &PhysicsState) {
        self.plant.set_state(&s.plant);
        self.strain.history.clone_from(&s.strain);
        self.load_rng.set(s.load_rng);
        self.monitor = s.monitor.clone();
    }

    /// The platform servo's Goal Position this cycle (ticks) and its top's height above the
    /// ground now, m.
    pub fn platform_state(&self) -> Option<(u32, f64)> {
        let r = self.platform.as_ref()?;
        Some((r.goal, self.plant.data.qpos()[r.qpos]))
    }

    /// The platform servo's bus ID (`None`: no platform).
    pub fn platform_servo_id(&self) -> Option<u8> {
        self.platform.as_ref().map(|r| r.servo_id)
    }

    /// Moves the slide's command for the cycle starting now toward the platform servo's Goal
    /// Position in `chain`, at its Profile Velocity, over one bus cycle of `dt_s`.
    fn drive_platform(&mut self, chain: &VirtualChain, dt_s: f64) {
        let Some(r) = self.platform.as_mut() else {
            return;
        };
        let Some(servo) = chain.servo(r.servo_id) else {
            return;
        };
        r.goal = servo.get(ct::GOAL_POSITION);
        if let Some(leg) = r.follow
            && r.goal != u32::from(LEVEL_TICKS)
        {
            r.follow = None;
            if let Some((_, p)) = self
                .plant
                .foot_positions()
                .into_iter()
                .find(|(l, _)| *l == leg)
            {
                self.plant.place_platform([p[0], p[1]]);
            }
        }
        let Some(r) = self.platform.as_mut() else {
            return;
        };
        let target = crate::platform::height_m(r.goal);
        r.command_m = match crate::platform::speed_m_s(servo.get(ct::PROFILE_VELOCITY)) {
            Some(v) => r.command_m + (target - r.command_m).clamp(-v * dt_s, v * dt_s),
            None => target,
        };
        self.plant.data.ctrl_mut()[r.actuator] = r.command_m;
    }

    /// The platform servo's motor state: the slide's height and speed in ticks (no torque
    /// reported).
    fn platform_motor(&self) -> Option<(u8, MotorState)> {
        let r = self.platform.as_ref()?;
        let rad_per_tick = std::f64::consts::TAU / 4096.0;
        let h = self.plant.data.qpos()[r.qpos];
        let v = self.plant.data.qvel()[r.qvel];
        Some((
            r.servo_id,
            MotorState {
                angle_rad: f64::from(crate::platform::ticks_at_height(h)) * rad_per_tick,
                velocity_rad_s: v / crate::platform::HEIGHT_PER_TICK_M * rad_per_tick,
                torque_nm: 0.0,
                duty: 0.0,
            },
        ))
    }

    /// The board's virtual robot (22 servos, and the platform's if it has one; erased gait
    /// store) with this body, its servos showing the body's state from power-on.
    pub fn into_board(self) -> PhysicsBoard {
        let mut servos = self.servos.clone();
        if let Some(r) = &self.platform {
            servos.push((r.servo_id, dynamixel::ServoModel::Mx28));
        }
        let mut chain = VirtualChain::new(&servos, Config::default().baud)
            .expect("the board's baud is a servo baud");
        chain.set_return_delay_all(0);
        self.power_on(&mut chain);
        VirtualRobot::with_parts(VirtualFlash::new(board::robot::FLASH_SECTORS), chain, self)
    }

    /// Powers `chain`'s servos on as this body's: each holds the Position P Gain nearest to its
    /// joint's stiffness in the model and the I and D Gains of its servo dynamics (from then on
    /// the registers are the actuator's gains, read every bus cycle:
    /// [`servo::gains_of_registers`]) and shows the body's state.
    pub fn power_on(&self, chain: &mut VirtualChain) {
        for j in self.plant.joints() {
            let p = servo::p_gain_for_stiffness(j.map.model, j.kp);
            if let Ok(s) = chain.servo_mut(j.map.id) {
                s.put(ct::POSITION_P_GAIN, u32::from(p));
                s.put(ct::POSITION_I_GAIN, u32::from(j.params.i_gain));
                s.put(ct::POSITION_D_GAIN, u32::from(j.params.d_gain));
            }
        }
        if let Some(id) = self.platform_servo_id()
            && let Ok(s) = chain.servo_mut(id)
        {
            // Level with the ground until the firmware writes a goal.
            s.put(ct::GOAL_POSITION, u32::from(LEVEL_TICKS));
        }
        self.push_state(chain);
    }

    /// A link to [`Self::into_board`], named `physics:SCENE[+SUBSTRATE][+platform:LEG]`.
    pub fn into_transport(self) -> PhysicsTransport {
        let mut name = match self.substrate {
            Substrate::Sandpaper => format!("physics:{}", self.scene),
            s => format!("physics:{}+{}", self.scene, s.name()),
        };
        if let Some(leg) = self.platform.as_ref().and_then(|r| r.follow) {
            name = format!("{name}+platform:{}", leg.name());
        }
        if let Some(file) = &self.model_file {
            name = format!("{name}+model:{file}");
        }
        VirtualTransport::named(self.into_board(), &name)
    }

    /// The ground it stands on.
    pub fn scene(&self) -> &Ground {
        &self.scene
    }

    /// The ground under the feet (its friction: [`crate::substrate::friction`]).
    pub fn substrate(&self) -> Substrate {
        self.substrate
    }

    /// The MuJoCo side.
    pub fn plant(&self) -> &Plant {
        &self.plant
    }

    /// The body's state now: thorax pose and velocity, foot contacts, simulated time.
    pub fn body(&self) -> crate::body::Body {
        self.plant.body()
    }

    /// The MuJoCo side, to change (e.g. cut a servo's stall torque).
    pub fn plant_mut(&mut self) -> &mut Plant {
        &mut self.plant
    }

    /// What the body did since power-on or [`Self::reset_figures`], sampled every bus cycle.
    pub fn figures(&self) -> Option<&Figures> {
        self.monitor.figures()
    }

    /// Switches the figures' sampling on (the default) or off: a caller that never reads
    /// [`Self::figures`] (the vector environment's robots) spares the monitor's work every bus
    /// cycle. Off, the figures stay as they were (None from power-on).
    pub fn set_figures(&mut self, on: bool) {
        self.figures_on = on;
    }

    /// Starts the figures afresh (e.g. when a walk starts).
    pub fn reset_figures(&mut self) {
        self.monitor.reset();
    }

    /// The latest sample of the simulated gauges (every [`crate::STRAIN_SAMPLE_S`] of simulated time,
    /// as the strain board's lines come; None before the first bus cycle).
    pub fn latest_strain(&self) -> Option<&SimulatedStrain> {
        self.strain.history.back()
    }

    /// The latest sample of the simulated gauges taken at or before `t_s` s of simulated time
    /// (the board's clock: a proprioception record's `time_us` x 1e-6); the last 3 s are kept.
    pub fn strain_at(&self, t_s: f64) -> Option<&SimulatedStrain> {
        self.strain.at(t_s)
    }

    /// The simulated gauges read now.
    pub fn strain_now(&self) -> SimulatedStrain {
        self.strain.gauges.read(&self.plant)
    }

    /// The simulated gauges' names, model order (the strain board's for the built-in robot).
    pub fn gauge_names(&self) -> Vec<String> {
        self.strain.gauges.names()
    }

    /// From now on each sample of the simulated gauges is also set into `feed`, by the strain
    /// board's channel names (a virtual strain board reads it: counts = baseline + gain x strain).
    pub fn feed_strain(&mut self, feed: board::strain::source::Shared) {
        self.strain.feed = Some(feed);
    }

    /// The thorax height of the planner's stance the body was set down in, m (the plan keeps it).
    pub fn planned_height_m(&self) -> f64 {
        self.planned_height_m
    }

    /// Starts a fresh [`WalkLog`]: from the next bus cycle on, one sample per cycle, a pose every
    /// `pose_every` cycles (0 counts as 1).
    pub fn start_log(&mut self, pose_every: usize) {
        self.log = Some(WalkLog {
            pose_every: pose_every.max(1),
            samples: Vec::new(),
        });
    }

    /// Ends logging and hands over what was logged (`None`: no log was started).
    pub fn take_log(&mut self) -> Option<WalkLog> {
        self.log.take()
    }

    fn log_sample(&mut self, controller: &Controller<VirtualFlash>) {
        let Some(log) = self.log.as_mut() else {
            return;
        };
        let pose = (log.samples.len() % log.pose_every == 0).then(|| {
            let mut q = vec![0.0; self.model_joints];
            for (i, j) in self.plant.joints().iter().enumerate() {
                q[j.joint] = self.plant.joint_state(i).0;
            }
            q
        });
        log.samples.push(WalkSample {
            time_s: self.plant.time(),
            playback: controller.playback(),
            walking: controller.state() == firmware::safety::State::Walking,
            thorax: self.plant.thorax_pose(),
            foot_forces: self.plant.foot_forces(),
            foot_spheres: self.plant.foot_positions(),
            pose,
            strain: None,
        });
    }

    /// Shows the servos of `chain` the body's state (their own motors stay still), their Present
    /// Load as the model's servo dynamics read it ([`servo::present_load`]).
    fn push_state(&self, chain: &mut VirtualChain) {
        for s in chain.servos_mut() {
            s.external_plant = true;
        }
        // Each joint's servo gets its state and then its noisy load (the load overwrites the
        // one the state sets), one servo lookup per joint and no lists: the platform's servo
        // and the joints' are distinct, so the order across servos changes nothing.
        for (i, j) in self.plant.joints().iter().enumerate() {
            let (q, qd, tau) = self.plant.joint_state(i);
            let d = self.plant.duty(i);
            let state = servo::motor_state(&j.map, q, qd, tau, d);
            let normal = if j.params.load_noise_nm > 0.0 {
                standard_normal(&self.load_rng)
            } else {
                0.0
            };
            let load = servo::present_load(j.map.model, &j.params, state.torque_nm, normal);
            if let Ok(s) = chain.servo_mut(j.map.id) {
                s.set_motor_state(state);
                s.put(ct::PRESENT_LOAD_OR_CURRENT, u32::from(load as u16));
            }
        }
        if let Some((id, state)) = self.platform_motor()
            && let Ok(s) = chain.servo_mut(id)
        {
            s.set_motor_state(state);
        }
    }
}

impl ServoDynamics for PhysicsRobot {
    /// Steps the body to the cycle's start under the goals the servos hold now, shows the servos
    /// the body's state, and samples the figures.
    fn before_cycle(
        &mut self,
        controller: &Controller<VirtualFlash>,
        chain: &mut VirtualChain,
        now_us: u64,
    ) {
        for i in 0..self.plant.joints().len() {
            let j = &self.plant.joints()[i];
            let (goal, on, gains) = match chain.servo(j.map.id) {
                Some(s) => (
                    servo::ticks_to_angle(&j.map, s.get(ct::GOAL_POSITION) as i32),
                    s.torque_enabled(),
                    // The gain registers are the actuator's gains (the P gain its stiffness).
                    Some(servo::gains_of_registers(
                        j.map.model,
                        &j.params,
                        s.get(ct::POSITION_P_GAIN) as u16,
                        s.get(ct::POSITION_I_GAIN) as u16,
                        s.get(ct::POSITION_D_GAIN) as u16,
                    )),
                ),
                // A servo the bus lacks holds nothing.
                None => (j.goal, false, None),
            };
            self.plant.set_goal(i, goal, on);
            if let Some((kp, ki, kd)) = gains {
                self.plant.set_kp(i, kp);
                self.plant.set_ki_kd(i, ki, kd);
            }
        }
        let now_s = now_us as f64 * 1e-6;
        match self.settle.take() {
            Some(Settle::Skip(t, state)) if now_s < t => self.settle = Some(Settle::Skip(t, state)),
            Some(Settle::Skip(_, state)) => self.set_state(&state),
            other => {
                self.settle = other;
                let dt_s = now_s - self.plant.time();
                self.drive_platform(chain, dt_s);
                self.plant.advance_to(now_s);
                if let Some(Settle::Keep(t)) = self.settle
                    && now_s >= t
                {
                    self.settle = Some(Settle::Kept(Box::new(self.state())));
                }
            }
        }
        self.push_state(chain);
        if self.figures_on {
            self.monitor.sample(&self.plant);
        }
        self.log_sample(controller);
        if self.strain.sample(&self.plant)
            && let Some(last) = self.log.as_mut().and_then(|l| l.samples.last_mut())
        {
            last.strain = self.strain.history.back().map(|s| s.microstrain());
        }
    }
}

/// A standard normal sample (Box-Muller on two uniforms of `planner::terrain::splitmix64`).
fn standard_normal(state: &std::cell::Cell<u64>) -> f64 {
    let uniform = || {
        state.set(planner::terrain::splitmix64(state.get()));
        ((state.get() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    let (u1, u2) = (uniform(), uniform());
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// The built-in Drosophibot II.
pub(crate) fn drosophibot() -> Result<Model, PhysicsError> {
    planner::model::builtin("drosophibot2").map_err(|e| PhysicsError::Load {
        model: "drosophibot2".into(),
        message: e.to_string(),
    })
}

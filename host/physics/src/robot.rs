//! [`PhysicsRobot`]: the virtual robot (the firmware library's board over the simulated Dynamixel
//! bus) whose servos are joints of a MuJoCo body. Before each bus cycle the plant steps to the
//! cycle's start under the goals the servos hold, and the servos' Present registers take the
//! body's angles, velocities and actuator torques; the firmware's cycle then reads them and writes
//! new goals. Within a cycle's few milliseconds of bus traffic the servos report the state at its
//! start (a real servo samples continuously: up to one cycle of extra latency here).
//!
//! This file is the only coupling to the virtual robot's API (`board::robot::VirtualRobot`).

use board::robot::VirtualRobot;
use dynamixel::control_table as ct;
use planner::model::{MjcfOptions, Model};

use crate::error::PhysicsError;
use crate::figures::{Figures, Monitor};
use crate::plant::Plant;
use crate::servo;

/// The physics robot's MuJoCo timestep, s: 1 ms, twice the MJCF export's default, for speed (the
/// contact's 2 ms time constant is still two steps). Halving it changes the walk's figures by
/// less than the bounds of tests/walk_figures.rs.
pub const TIMESTEP_S: f64 = 0.001;

/// A simulated board with a simulated body.
#[derive(Debug)]
pub struct PhysicsRobot {
    robot: VirtualRobot,
    plant: Plant,
    scene: String,
    monitor: Monitor,
}

impl PhysicsRobot {
    /// Drosophibot II (the built-in model) on `scene` (`flat`, `incline:DEG`, `ball`, `ball-fixed`).
    pub fn drosophibot(scene: &str) -> Result<Self, PhysicsError> {
        let model = planner::model::builtin("drosophibot2").map_err(|e| PhysicsError::Load {
            model: "drosophibot2".into(),
            message: e.to_string(),
        })?;
        Self::new(&model, scene)
    }

    /// `model` on `scene`, standing in the planner's resting posture, its servos switched off,
    /// stepped at [`TIMESTEP_S`].
    pub fn new(model: &Model, scene: &str) -> Result<Self, PhysicsError> {
        Self::with_options(model, &Self::options(model, scene)?, scene)
    }

    /// The MJCF options [`Self::new`] uses: the planner's stance on `scene`, at [`TIMESTEP_S`].
    pub fn options(model: &Model, scene: &str) -> Result<MjcfOptions, PhysicsError> {
        let mut options =
            MjcfOptions::stance(model, scene).map_err(|source| PhysicsError::Scene {
                model: model.name.clone(),
                scene: scene.to_owned(),
                source,
            })?;
        options.timestep_s = TIMESTEP_S;
        Ok(options)
    }

    /// `model` with explicit MJCF options (e.g. another timestep); `scene` names it in messages.
    pub fn with_options(
        model: &Model,
        options: &MjcfOptions,
        scene: &str,
    ) -> Result<Self, PhysicsError> {
        let plant = Plant::new(model, options)?;
        let mut r = Self {
            robot: VirtualRobot::new(),
            plant,
            scene: scene.to_owned(),
            monitor: Monitor::new(),
        };
        r.push_state();
        Ok(r)
    }

    /// The scene's name.
    pub fn scene(&self) -> &str {
        &self.scene
    }

    /// The MuJoCo side.
    pub fn plant(&self) -> &Plant {
        &self.plant
    }

    /// The MuJoCo side, to change (e.g. cut a servo's stall torque).
    pub fn plant_mut(&mut self) -> &mut Plant {
        &mut self.plant
    }

    /// What the body did since power-on or [`Self::reset_figures`], sampled every bus cycle.
    pub fn figures(&self) -> Option<&Figures> {
        self.monitor.figures()
    }

    /// Starts the figures afresh (e.g. when a walk starts).
    pub fn reset_figures(&mut self) {
        self.monitor.reset();
    }

    /// The board side (controller, servo chain, timing).
    pub fn board(&self) -> &VirtualRobot {
        &self.robot
    }

    /// Simulated time since power-on, us.
    pub fn now_us(&self) -> u64 {
        self.robot.now_us()
    }

    /// Bytes from the host.
    pub fn receive(&mut self, bytes: &[u8]) {
        self.robot.receive(bytes);
    }

    /// Bytes waiting for the host.
    pub fn pending(&self) -> usize {
        self.robot.pending()
    }

    /// Moves up to `buf.len()` bytes for the host into `buf`.
    pub fn take(&mut self, buf: &mut [u8]) -> usize {
        self.robot.take(buf)
    }

    /// Start of the next bus cycle, us.
    pub fn next_cycle_us(&self) -> u64 {
        self.robot.next_cycle_us()
    }

    /// The body moves to the next cycle's start, then the firmware runs that cycle.
    pub fn cycle(&mut self) {
        let t = self.robot.next_cycle_us().max(self.robot.now_us());
        self.advance_body(t);
        self.monitor.sample(&self.plant);
        self.robot.cycle();
    }

    /// Lets time pass up to `t_us`, running every bus cycle that starts before it.
    pub fn run_until(&mut self, t_us: u64) {
        while self.robot.next_cycle_us() <= t_us {
            self.cycle();
        }
        self.advance_body(t_us);
        self.robot.run_until(t_us);
    }

    /// Steps the body to `t_us` under the goals the servos hold now, then shows the servos the
    /// body's state.
    fn advance_body(&mut self, t_us: u64) {
        let goals: Vec<(f64, bool)> = self.robot.with_chain(|chain| {
            self.plant
                .joints()
                .iter()
                .map(|j| match chain.servo(j.map.id) {
                    Some(s) => (
                        servo::ticks_to_angle(&j.map, s.get(ct::GOAL_POSITION) as i32),
                        s.torque_enabled(),
                    ),
                    // A servo the bus lacks holds nothing.
                    None => (j.goal, false),
                })
                .collect()
        });
        for (i, (goal, on)) in goals.into_iter().enumerate() {
            self.plant.set_goal(i, goal, on);
        }
        self.plant.advance_to(t_us as f64 * 1e-6);
        self.push_state();
    }

    fn push_state(&mut self) {
        let states: Vec<(u8, dynamixel::sim::physics::MotorState)> = (0..self.plant.joints().len())
            .map(|i| {
                let j = &self.plant.joints()[i];
                let (q, qd, tau) = self.plant.joint_state(i);
                let d = servo::duty(q, j.goal, j.torque_on, j.kp, j.stall);
                (j.map.id, servo::motor_state(&j.map, q, qd, tau, d))
            })
            .collect();
        self.robot.with_chain(|chain| {
            for s in chain.servos_mut() {
                s.external_plant = true;
            }
            for (id, state) in states {
                if let Ok(s) = chain.servo_mut(id) {
                    s.set_motor_state(state);
                }
            }
        });
    }
}

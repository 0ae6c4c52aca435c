//! The servos of the virtual robot, seen from the controller's bus actions: each servo is a
//! position loop of stiffness `k` that settles with a first-order lag towards the pose where its
//! torque balances the external load (the planned joint torque the leg must carry).
//!
//! This is a behavioural model at the level of the controller's [`CyclePlan`] / [`Outcome`]
//! exchange, not the Dynamixel wire (that is the dynamixel crate's virtual chain). Its numbers are
//! ESTIMATES: the stiffness comes from the default P gain through
//! `dynamixel::units::stiffness_nm_per_rad`, load registers through `dynamixel::units::torque_to_load`,
//! and the time constant is [`TIME_CONSTANT_S`].

use std::collections::BTreeMap;

use dynamixel::control_table::Model;
use dynamixel::master::{CycleStats, Feedback, MasterConfig, Reply};
use dynamixel::units::{
    RAD_PER_TICK, RAD_S_PER_VELOCITY_UNIT, stiffness_nm_per_rad, torque_to_load,
};
use firmware::controller::{BusAction, CyclePlan, Outcome};

/// Settling time constant of a servo's position loop, s (ESTIMATE: an MX-28 at the default gains
/// reaches a small step in tens of milliseconds).
pub const TIME_CONSTANT_S: f64 = 0.02;
/// Position P Gain the servos run with (the MX(2.0) default).
pub const P_GAIN: u16 = 850;
/// Turnaround of a servo before its status packet, us (Return Delay Time 0 plus processing).
const TURNAROUND_US: u32 = 20;

/// One simulated servo.
#[derive(Debug, Clone, PartialEq)]
pub struct SimServo {
    pub model: Model,
    /// Present position, ticks (fractional: the model is continuous).
    pub position: f64,
    pub goal: f64,
    pub torque_on: bool,
    /// Velocity of the last step, ticks/s.
    pub velocity: f64,
    /// Torque the load asks of the servo, N m in the servo's tick direction.
    pub load_nm: f64,
}

impl SimServo {
    /// Stiffness of the position loop, N m per tick.
    fn stiffness_per_tick(&self) -> f64 {
        f64::from(stiffness_nm_per_rad(self.model, P_GAIN)) * f64::from(RAD_PER_TICK)
    }

    /// Torque the servo produces now, N m (what its load register reports).
    pub fn output_nm(&self) -> f64 {
        if self.torque_on {
            self.stiffness_per_tick() * (self.goal - self.position)
        } else {
            0.0
        }
    }

    fn step(&mut self, dt_s: f64) {
        let before = self.position;
        if self.torque_on {
            // Equilibrium: k (goal - x) = load.
            let target = self.goal - self.load_nm / self.stiffness_per_tick();
            let a = 1.0 - (-dt_s / TIME_CONSTANT_S).exp();
            self.position += (target - self.position) * a;
        }
        self.velocity = if dt_s > 0.0 {
            (self.position - before) / dt_s
        } else {
            0.0
        };
    }

    fn feedback(&self) -> Feedback {
        let rad_s = self.velocity * f64::from(RAD_PER_TICK);
        Feedback {
            load: torque_to_load(self.model, self.output_nm() as f32),
            velocity: (rad_s / f64::from(RAD_S_PER_VELOCITY_UNIT)).round() as i32,
            position: self.position.round() as i32,
            alert: false,
        }
    }
}

/// The chain of simulated servos, keyed by bus ID.
#[derive(Debug, Clone, Default)]
pub struct SimServos {
    servos: BTreeMap<u8, SimServo>,
}

impl SimServos {
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds (or replaces) servo `id` lying at `position` ticks with torque off.
    pub fn add(&mut self, id: u8, model: Model, position: f64) {
        self.servos.insert(
            id,
            SimServo {
                model,
                position,
                goal: position,
                torque_on: false,
                velocity: 0.0,
                load_nm: 0.0,
            },
        );
    }

    pub fn get(&self, id: u8) -> Option<&SimServo> {
        self.servos.get(&id)
    }

    /// Sets the torque the load asks of servo `id`, N m in its tick direction.
    pub fn set_load(&mut self, id: u8, load_nm: f64) {
        if let Some(s) = self.servos.get_mut(&id) {
            s.load_nm = load_nm;
        }
    }

    /// Performs `plan` after `dt_s` seconds of motion since the previous action; fills `replies`
    /// for the servos the plan addresses (a servo that does not exist times out, as on the bus).
    pub fn perform(
        &mut self,
        plan: &CyclePlan,
        dt_s: f64,
        baud: u32,
        replies: &mut [Reply],
    ) -> Outcome {
        for s in self.servos.values_mut() {
            s.step(dt_s);
        }
        let goals = plan.goals();
        match plan.action {
            BusAction::Nothing => Outcome::Done(Ok(())),
            BusAction::Cycle | BusAction::ReadOnly => {
                if plan.action == BusAction::Cycle {
                    for g in goals {
                        if let Some(s) = self.servos.get_mut(&g.id) {
                            s.goal = f64::from(g.position);
                        }
                    }
                }
                let mut stats = CycleStats {
                    start_us: plan.start_us,
                    ..Default::default()
                };
                for (r, g) in replies.iter_mut().zip(goals) {
                    match self.servos.get(&g.id) {
                        Some(s) => {
                            *r = Ok(s.feedback());
                            stats.ok += 1;
                        }
                        None => stats.timeouts += 1,
                    }
                }
                let n = goals.len();
                let write = if plan.action == BusAction::Cycle {
                    14 + 5 * n
                } else {
                    0
                };
                let cfg = MasterConfig::new(baud);
                let busy = cfg.wire_time_us(write + 14 + n) as u64
                    + (cfg.wire_time_us(21) + TURNAROUND_US) as u64 * u64::from(stats.ok);
                stats.tx_end_us = plan.start_us + u64::from(cfg.wire_time_us(write + 14 + n));
                stats.end_us = plan.start_us + busy;
                Outcome::Feedback(Ok(stats))
            }
            BusAction::TorqueOn => {
                for g in goals {
                    if let Some(s) = self.servos.get_mut(&g.id) {
                        s.goal = f64::from(g.position);
                        s.torque_on = true;
                    }
                }
                Outcome::Done(Ok(()))
            }
            BusAction::TorqueOff | BusAction::Reboot => {
                for g in goals {
                    if let Some(s) = self.servos.get_mut(&g.id) {
                        s.torque_on = false;
                    }
                }
                Outcome::Done(Ok(()))
            }
            BusAction::ReadHardwareError { .. } => Outcome::HardwareError(Ok(0)),
        }
    }
}

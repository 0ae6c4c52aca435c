//! Can the servos follow a plan? Peak joint speed, acceleration and torque per joint against the
//! servo's datasheet limits, and jumps of the inverse kinematics between slices (a change of
//! branch that no servo can follow).
//!
//! Limits are the Dynamixel e-manual datasheet values at 12 V (no-load speed, stall torque); the
//! torque a servo can give while turning is estimated from the DC motor's linear torque-speed
//! line, T_avail = T_stall (1 - |w| / w_0), when the joint drives its motion (T w > 0). The
//! datasheets give no acceleration limit: peaks are reported, not checked.

use crate::model::{Actuation, ActuatorKind, Model};
use crate::plan::periodic_central_difference;

/// Datasheet limits of a servo at 12 V.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServoLimits {
    pub name: &'static str,
    /// No-load speed, rad/s.
    pub no_load_speed: f64,
    /// Stall torque, N m.
    pub stall_torque: f64,
}

/// The servo limits of an actuator family (none for a generic actuator such as the fly's muscles).
/// The one place the planner reads the servo constants ([`dynamixel::ServoModel`]).
pub fn servo_limits(kind: ActuatorKind) -> Option<ServoLimits> {
    dynamixel::ServoModel::try_from(kind)
        .ok()
        .map(ServoLimits::of)
}

impl ServoLimits {
    /// The datasheet limits of `servo` (e-manual, 12 V).
    pub fn of(servo: dynamixel::ServoModel) -> Self {
        Self {
            name: servo.name(),
            no_load_speed: f64::from(servo.no_load_speed_rad_s()),
            stall_torque: f64::from(servo.stall_torque_nm()),
        }
    }
}

/// A peak value over the cycle and the slice where it occurs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Peak {
    pub value: f64,
    pub slice: usize,
}

/// Peaks of one actuated joint.
#[derive(Debug, Clone, PartialEq)]
pub struct JointPeaks {
    pub joint: String,
    pub limits: Option<ServoLimits>,
    /// |qd|, rad/s.
    pub speed: Peak,
    /// |qdd|, rad/s^2.
    pub acceleration: Peak,
    /// |actuator torque|, N m (when torques are known).
    pub torque: Option<Peak>,
    /// Smallest T_avail - |T| over the slices where the joint drives its motion, N m.
    pub torque_speed_margin: Option<Peak>,
}

/// Something a servo cannot do, at one slice.
#[derive(Debug, Clone, PartialEq)]
pub enum Violation {
    /// Faster than the servo's no-load speed.
    Speed {
        joint: String,
        slice: usize,
        speed: f64,
        limit: f64,
    },
    /// More than the stall torque.
    Torque {
        joint: String,
        slice: usize,
        torque: f64,
        limit: f64,
    },
    /// Within the stall torque but above the torque-speed line at that speed.
    TorqueAtSpeed {
        joint: String,
        slice: usize,
        torque: f64,
        speed: f64,
        available: f64,
    },
    /// The IK changed branch: one slice's step is far larger than its neighbours'.
    Jump {
        joint: String,
        slice: usize,
        step: f64,
    },
}

impl std::fmt::Display for Violation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Violation::Speed {
                joint,
                slice,
                speed,
                limit,
            } => write!(
                f,
                "{joint} at slice {slice}: {speed:.2} rad/s, over the servo's no-load speed {limit:.2} rad/s by {:.2} rad/s ({:.0} %)",
                speed - limit,
                100.0 * (speed / limit - 1.0)
            ),
            Violation::Torque {
                joint,
                slice,
                torque,
                limit,
            } => write!(
                f,
                "{joint} at slice {slice}: |torque| {torque:.3} N m, over the stall torque {limit:.2} N m by {:.3} N m",
                torque - limit
            ),
            Violation::TorqueAtSpeed {
                joint,
                slice,
                torque,
                speed,
                available,
            } => write!(
                f,
                "{joint} at slice {slice}: |torque| {torque:.3} N m at {speed:.2} rad/s, over the {available:.3} N m the servo gives at that speed (torque-speed line, estimate) by {:.3} N m",
                torque - available
            ),
            Violation::Jump { joint, slice, step } => write!(
                f,
                "{joint} between slices {slice} and {}: jumps {step:.3} rad (an inverse-kinematics branch change)",
                slice + 1
            ),
        }
    }
}

/// Peaks per actuated joint and everything no servo could follow.
#[derive(Debug, Clone, PartialEq)]
pub struct Feasibility {
    pub joints: Vec<JointPeaks>,
    pub violations: Vec<Violation>,
}

impl Feasibility {
    pub fn is_feasible(&self) -> bool {
        self.violations.is_empty()
    }

    /// One line per joint with limits: peaks and the margin to them.
    pub fn table(&self) -> String {
        let mut out = String::from(
            "| joint | servo | peak speed (rad/s) | no-load (rad/s) | peak accel (rad/s^2) | peak torque (N m) | stall (N m) | torque-speed margin (N m) |\n|---|---|---|---|---|---|---|---|\n",
        );
        for j in &self.joints {
            let (name, w0, ts) = j.limits.map_or(("-", "-".into(), "-".into()), |l| {
                (
                    l.name,
                    format!("{:.2}", l.no_load_speed),
                    format!("{:.2}", l.stall_torque),
                )
            });
            let opt = |p: Option<Peak>| p.map_or("-".into(), |p| format!("{:.3e}", p.value));
            out += &format!(
                "| {} | {name} | {:.3} | {w0} | {:.3e} | {} | {ts} | {} |\n",
                j.joint,
                j.speed.value,
                j.acceleration.value,
                opt(j.torque),
                opt(j.torque_speed_margin)
            );
        }
        out
    }
}

/// A step larger than this (rad) and [`JUMP_RATIO`] times both neighbouring steps is a jump.
pub const JUMP_MIN_RAD: f64 = 0.1;
pub const JUMP_RATIO: f64 = 2.0;

/// Checks angles `q[slice][joint]` (a periodic cycle of slices `dt` apart) and, when known, the
/// actuator torques `torque[slice][joint]` against each joint's servo.
pub fn check(model: &Model, q: &[Vec<f64>], torque: Option<&[Vec<f64>]>, dt: f64) -> Feasibility {
    let servos: Vec<Servo<'_>> = model
        .joints
        .iter()
        .enumerate()
        .filter_map(|(column, joint)| match &joint.actuation {
            Actuation::Actuated { actuator, .. } => Some(Servo {
                column,
                joint: &joint.name,
                limits: servo_limits(*actuator),
            }),
            Actuation::Fixed { .. } => None,
        })
        .collect();
    check_servos(&servos, q, torque, dt)
}

/// One servo-driven column of the angles handed to [`check_servos`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Servo<'a> {
    /// Column of `q[slice]` (and `torque[slice]`) holding the joint.
    pub column: usize,
    /// The joint's full name, as violations name it.
    pub joint: &'a str,
    /// The servo's limits (none: reported, not checked).
    pub limits: Option<ServoLimits>,
}

/// [`check`] over the columns `servos` of `q` (and `torque`): for angles that are not a model's
/// joint order, such as a step table's joints.
pub fn check_servos(
    servos: &[Servo<'_>],
    q: &[Vec<f64>],
    torque: Option<&[Vec<f64>]>,
    dt: f64,
) -> Feasibility {
    let qd = periodic_central_difference(q, dt);
    let qdd = periodic_central_difference(&qd, dt);
    let n = q.len();
    let mut joints = Vec::new();
    let mut violations = Vec::new();
    for servo in servos {
        let (j, limits) = (servo.column, servo.limits);
        let joint = servo.joint;
        let peak = |v: &dyn Fn(usize) -> f64| {
            (0..n).fold(
                Peak {
                    value: 0.0,
                    slice: 0,
                },
                |p, s| {
                    if v(s) > p.value {
                        Peak {
                            value: v(s),
                            slice: s,
                        }
                    } else {
                        p
                    }
                },
            )
        };
        let speed = peak(&|s| qd[s][j].abs());
        let acceleration = peak(&|s| qdd[s][j].abs());
        let tq = torque.map(|t| peak(&|s| t[s][j].abs()));
        let mut margin = None;
        if let Some(l) = limits {
            if speed.value > l.no_load_speed {
                violations.push(Violation::Speed {
                    joint: joint.to_owned(),
                    slice: speed.slice,
                    speed: speed.value,
                    limit: l.no_load_speed,
                });
            }
            if let Some(t) = torque {
                if let Some(p) = tq.filter(|p| p.value > l.stall_torque) {
                    violations.push(Violation::Torque {
                        joint: joint.to_owned(),
                        slice: p.slice,
                        torque: p.value,
                        limit: l.stall_torque,
                    });
                }
                let mut worst: Option<(Peak, f64, f64)> = None;
                for s in (0..n).filter(|&s| t[s][j] * qd[s][j] > 0.0) {
                    let w = qd[s][j].abs();
                    let available = (l.stall_torque * (1.0 - w / l.no_load_speed)).max(0.0);
                    let m = available - t[s][j].abs();
                    if worst.is_none_or(|(p, _, _)| m < p.value) {
                        worst = Some((Peak { value: m, slice: s }, w, available));
                    }
                }
                if let Some((p, w, available)) = worst {
                    margin = Some(p);
                    let over_stall = tq.is_some_and(|t| t.value > l.stall_torque);
                    if p.value < 0.0 && w <= l.no_load_speed && !over_stall {
                        violations.push(Violation::TorqueAtSpeed {
                            joint: joint.to_owned(),
                            slice: p.slice,
                            torque: t[p.slice][j].abs(),
                            speed: w,
                            available,
                        });
                    }
                }
            }
        }
        violations.extend(
            jumps(q, j)
                .into_iter()
                .map(|(slice, step)| Violation::Jump {
                    joint: joint.to_owned(),
                    slice,
                    step,
                }),
        );
        joints.push(JointPeaks {
            joint: joint.to_owned(),
            limits,
            speed,
            acceleration,
            torque: tq,
            torque_speed_margin: margin,
        });
    }
    Feasibility { joints, violations }
}

/// Slices `s` where joint `j`'s step to slice `s + 1` (cyclically) is a jump: over
/// [`JUMP_MIN_RAD`] and over [`JUMP_RATIO`] times the steps before and after it.
pub fn jumps(q: &[Vec<f64>], j: usize) -> Vec<(usize, f64)> {
    let n = q.len();
    if n < 3 {
        return vec![];
    }
    let step = |s: usize| (q[(s + 1) % n][j] - q[s % n][j]).abs();
    (0..n)
        .filter_map(|s| {
            let d = step(s);
            let (before, after) = (step(s + n - 1), step(s + 1));
            (d > JUMP_MIN_RAD && d > JUMP_RATIO * before && d > JUMP_RATIO * after)
                .then_some((s, d))
        })
        .collect()
}

//! Servo dynamics in the model file (docs/models.md, "Servo dynamics"): per servo model
//! (`[servo_dynamics.mx28]`) with per-joint overrides (a joint's `servo_dynamics = { ... }`),
//! every field optional. A field given nowhere takes its default from [`ServoParams::defaults`]:
//! e-manual figures through [`dynamixel::ServoModel`] (the one owner of servo constants) or an
//! ESTIMATE that leaves the physics robot as it was before these fields existed (no friction,
//! deadband or backlash, an exact Present Load). Precedence: the joint's field, else its servo
//! model's, else the default.
//!
//! The physics robot (`physics` crate) uses every field: gains, deadband, backlash, the
//! torque-speed line and the Present Load reading in its servo, and damping, friction and
//! armature as MuJoCo's joint `damping`, `frictionloss` and `armature` in the MJCF export.

use serde::{Deserialize, Serialize};

use super::error::{ModelError, field};
use super::types::{Actuation, ActuatorKind, Model};

/// Declares the fields once: the resolved [`ServoParams`], the file's [`ServoParamsEntry`]
/// (every field optional), how an entry overrides, and each field's range and unit.
macro_rules! servo_fields {
    ($($(#[$doc:meta])* $name:ident: $ty:ty, $unit:literal, $lo:expr, $hi:expr;)*) => {
        /// Every servo-dynamics parameter of one joint's servo, resolved
        /// ([`Model::servo_params`]). Units are SI unless a field says counts or a register.
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub struct ServoParams {
            $($(#[$doc])* pub $name: $ty,)*
        }

        /// The servo-dynamics fields a model file gives for a servo model or a joint: each one
        /// optional, overriding what comes before it ([`ServoParams::with`]).
        #[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct ServoParamsEntry {
            $($(#[$doc])*
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub $name: Option<$ty>,)*
        }

        impl ServoParams {
            /// These parameters with every field `entry` gives replaced by its value.
            pub fn with(mut self, entry: &ServoParamsEntry) -> Self {
                $(if let Some(v) = entry.$name {
                    self.$name = v;
                })*
                self
            }
        }

        /// Every field: its name in the file, unit and allowed range.
        pub const SERVO_FIELDS: &[FieldRange] = &[
            $(FieldRange { name: stringify!($name), unit: $unit, min: $lo, max: $hi },)*
        ];

        impl ServoParamsEntry {
            /// The given fields as `(name, value)`, in declaration order.
            pub fn given(&self) -> Vec<(&'static str, f64)> {
                let mut out = Vec::new();
                $(if let Some(v) = self.$name {
                    out.push((stringify!($name), f64::from(v)));
                })*
                out
            }
        }
    };
}

/// One servo-dynamics field's unit and allowed range (inclusive): the ranges are far beyond any
/// servo of this class and only keep the arithmetic meaningful, as the model's other ranges do.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FieldRange {
    pub name: &'static str,
    pub unit: &'static str,
    pub min: f64,
    pub max: f64,
}

servo_fields! {
    /// Divisor of the Position P Gain register: Kp = P / divisor, in PWM per tick of error. The
    /// e-manual's 128 (ESTIMATE: BAM measured 256 on X-series servos). The register itself is
    /// the firmware's, written from the joint's `stiffness_nm_per_rad`; this says what stiffness
    /// the servo really makes of it.
    p_gain_divisor: f64, "", 1.0, 65_536.0;
    /// Position I Gain register the servo holds (e-manual default 0; Ki = I / 65536).
    i_gain: u16, "", 0.0, 16_383.0;
    /// Position D Gain register the servo holds (e-manual default 0; Kd = D / 16).
    d_gain: u16, "", 0.0, 16_383.0;
    /// Viscous damping of the gear train, N m s/rad, beside the motor's back-EMF (which is the
    /// torque-speed line): MuJoCo's joint `damping`. ESTIMATE 0 (not in the e-manual; BAM's fitted
    /// MX-64: 0.0117).
    damping_nm_s_per_rad: f64, "N m s/rad", 0.0, 100.0;
    /// Coulomb friction of the gear train, N m: MuJoCo's joint `frictionloss`. ESTIMATE 0 (not in
    /// the e-manual; BAM's fitted MX-64: 0.090).
    friction_nm: f64, "N m", 0.0, 100.0;
    /// Rotor inertia seen at the output, kg m^2: MuJoCo's joint `armature`. ESTIMATE
    /// ([`dynamixel::ServoModel::armature_kg_m2`]).
    armature_kg_m2: f64, "kg m^2", 0.0, 10.0;
    /// Position error the controller ignores, rad: within it the servo gives no torque, beyond it
    /// the error less the deadband counts. ESTIMATE 0 (the e-manual publishes none).
    deadband_rad: f64, "rad", 0.0, 0.2;
    /// Total play of the gear train, rad: after a reversal the motor crosses it before the
    /// output is driven again. ESTIMATE 0 (the e-manual publishes none; hobby servos of this
    /// class have a fraction of a degree).
    backlash_rad: f64, "rad", 0.0, 0.2;
    /// Stall torque, N m: the torque-speed line's torque at zero speed (e-manual, 12 V).
    stall_torque_nm: f64, "N m", 1e-3, 1_000.0;
    /// No-load speed, rad/s: the torque-speed line's speed at zero torque (e-manual, 12 V).
    no_load_speed_rad_s: f64, "rad/s", 1e-3, 1_000.0;
    /// Present Load reading: the servo reports `load_gain` x torque + `load_offset_nm` through
    /// the register's conversion (`dynamixel::units::torque_to_load`). ESTIMATE 1 (ROBOTIS
    /// calls the MX-28's load inferred, not measured).
    load_gain: f64, "", 1e-3, 1_000.0;
    /// Present Load offset, N m. ESTIMATE 0.
    load_offset_nm: f64, "N m", -100.0, 100.0;
    /// Present Load resolution, register counts (0.1 % of maximum on the MX-28, 3.36 mA on the
    /// MX-64): readings fall on multiples of it. ESTIMATE 1 (the register's unit).
    load_resolution_counts: u16, "counts", 1.0, 1_000.0;
    /// Present Load noise, N m: the standard deviation of Gaussian noise added to the reading
    /// (a fixed-seed generator). ESTIMATE 0.
    load_noise_nm: f64, "N m", 0.0, 100.0;
}

impl ServoParams {
    /// The defaults of `servo`: e-manual figures where it has them, else the ESTIMATE that
    /// leaves the physics robot as it was (see each field).
    pub fn defaults(servo: protocol::ServoModel) -> Self {
        Self {
            p_gain_divisor: f64::from(dynamixel::model::P_GAIN_DIVISOR),
            i_gain: dynamixel::model::I_GAIN_DEFAULT,
            d_gain: dynamixel::model::D_GAIN_DEFAULT,
            damping_nm_s_per_rad: 0.0,
            friction_nm: 0.0,
            armature_kg_m2: servo.armature_kg_m2(),
            deadband_rad: 0.0,
            backlash_rad: 0.0,
            stall_torque_nm: f64::from(servo.stall_torque_nm()),
            no_load_speed_rad_s: f64::from(servo.no_load_speed_rad_s()),
            load_gain: 1.0,
            load_offset_nm: 0.0,
            load_resolution_counts: 1,
            load_noise_nm: 0.0,
        }
    }

    /// The slope of the torque-speed line, N m s/rad: stall torque over no-load speed (the
    /// motor's back-EMF damping).
    pub fn back_emf_nm_s_per_rad(&self) -> f64 {
        self.stall_torque_nm / self.no_load_speed_rad_s
    }

    /// The torque the servo gives at full duty turning at `speed` rad/s in the direction it
    /// drives: `stall (1 - speed / no-load speed)`, clamped to `0 ..= stall`.
    pub fn torque_at_speed(&self, speed: f64) -> f64 {
        (self.stall_torque_nm * (1.0 - speed / self.no_load_speed_rad_s))
            .clamp(0.0, self.stall_torque_nm)
    }
}

/// A model's servo dynamics as its file gives them: per servo model and per joint, each only the
/// fields given ([`Model::servo_params`] resolves a joint's).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct ServoDynamics {
    /// `[servo_dynamics.<model>]`, in file order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub per_model: Vec<(protocol::ServoModel, ServoParamsEntry)>,
    /// A joint's `servo_dynamics`, by joint name.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub per_joint: Vec<(String, ServoParamsEntry)>,
}

impl ServoDynamics {
    /// What the file gives for servo model `servo`.
    pub fn of_model(&self, servo: protocol::ServoModel) -> Option<&ServoParamsEntry> {
        self.per_model
            .iter()
            .find(|(m, _)| *m == servo)
            .map(|(_, e)| e)
    }

    /// What the file gives for joint `name`.
    pub fn of_joint(&self, name: &str) -> Option<&ServoParamsEntry> {
        self.per_joint
            .iter()
            .find(|(j, _)| j == name)
            .map(|(_, e)| e)
    }

    /// Sets servo model `servo`'s entry (replacing one it had).
    pub fn set_model(&mut self, servo: protocol::ServoModel, entry: ServoParamsEntry) {
        self.per_model.retain(|(m, _)| *m != servo);
        self.per_model.push((servo, entry));
    }

    /// Sets joint `name`'s entry (replacing one it had).
    pub fn set_joint(&mut self, name: &str, entry: ServoParamsEntry) {
        self.per_joint.retain(|(j, _)| j != name);
        self.per_joint.push((name.to_owned(), entry));
    }
}

impl Model {
    /// The servo dynamics of joint `joint`: the defaults of its servo model, overridden by the
    /// model's `[servo_dynamics.<model>]`, overridden by the joint's own; `None` for a joint
    /// without a servo (fixed, or a generic actuator).
    pub fn servo_params(&self, joint: usize) -> Option<ServoParams> {
        let j = self.joints.get(joint)?;
        let Actuation::Actuated {
            actuator: ActuatorKind::Servo(servo),
            ..
        } = j.actuation
        else {
            return None;
        };
        let mut p = ServoParams::defaults(servo);
        if let Some(e) = self.servo_dynamics.of_model(servo) {
            p = p.with(e);
        }
        if let Some(e) = self.servo_dynamics.of_joint(&j.name) {
            p = p.with(e);
        }
        if let Some(c) = self.calibration.as_ref().and_then(|c| c.joint(&j.name)) {
            p.load_gain = c.load_gain;
            p.load_offset_nm = c.load_offset_nm;
        }
        Some(p)
    }

    /// Every servo-dynamics field in its range, each joint override on a joint that has a
    /// servo, and each joint's resolved friction below its stall torque (else the servo could
    /// never move); the error names the section or joint, the field and the range.
    pub(crate) fn check_servo_dynamics(&self, file: &str) -> Result<(), ModelError> {
        for (servo, entry) in &self.servo_dynamics.per_model {
            check_entry(file, &format!("servo_dynamics.{}", servo.key()), "", entry)?;
        }
        for (name, entry) in &self.servo_dynamics.per_joint {
            let place = format!("joint {name}");
            let Some(j) = self.joint_index(name) else {
                return Err(ModelError::Unknown {
                    file: file.to_owned(),
                    place: "servo_dynamics".into(),
                    what: "joint",
                    name: name.clone(),
                });
            };
            if self.servo_params(j).is_none() {
                return Err(field(
                    file,
                    place,
                    "servo_dynamics",
                    format!(
                        "the joint has no servo ({}): servo dynamics belong to a joint driven by a servo model",
                        self.joints[j].actuation
                    ),
                ));
            }
            check_entry(file, &place, "servo_dynamics.", entry)?;
        }
        for (j, joint) in self.joints.iter().enumerate() {
            let Some(p) = self.servo_params(j) else {
                continue;
            };
            if p.friction_nm >= p.stall_torque_nm {
                return Err(field(
                    file,
                    format!("joint {}", joint.name),
                    "servo_dynamics.friction_nm",
                    format!(
                        "{} N m is not below the stall torque {} N m: the servo could never move",
                        p.friction_nm, p.stall_torque_nm
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// Every field `entry` gives within its range; `prefix` goes before the field's name.
fn check_entry(
    file: &str,
    place: &str,
    prefix: &str,
    entry: &ServoParamsEntry,
) -> Result<(), ModelError> {
    for (name, value) in entry.given() {
        let r = SERVO_FIELDS
            .iter()
            .find(|r| r.name == name)
            .expect("every given field is declared");
        if !(value.is_finite() && (r.min..=r.max).contains(&value)) {
            let unit = if r.unit.is_empty() {
                String::new()
            } else {
                format!(" {}", r.unit)
            };
            return Err(field(
                file,
                place,
                &format!("{prefix}{name}"),
                format!("{value}{unit} is outside {} ..= {}{unit}", r.min, r.max),
            ));
        }
    }
    Ok(())
}

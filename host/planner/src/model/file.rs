//! The TOML model file format (documented in docs/models.md): its schema, and reading it into a
//! [`Model`] with validation that names the file, the body or joint and the field.

use super::error::{ModelError, field};
use super::spring::SpringEntry;
use super::*;
use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, Unit, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

/// A model file as written on disk. Names link joints to bodies; every number is SI.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelFile {
    pub name: String,
    /// Free text: where the numbers come from, conventions, caveats.
    #[serde(default)]
    pub notes: String,
    #[serde(rename = "body")]
    pub bodies: Vec<BodyEntry>,
    #[serde(rename = "joint")]
    pub joints: Vec<JointEntry>,
    #[serde(rename = "foot")]
    pub feet: Vec<FootEntry>,
    /// Strain gauges (docs/strain.md); optional.
    #[serde(default, rename = "gauge", skip_serializing_if = "Vec::is_empty")]
    pub gauges: Vec<super::GaugeEntry>,
    /// Servo dynamics per servo model (`[servo_dynamics.mx28]`), by the model's `actuation`
    /// name; each field optional (docs/models.md, "Servo dynamics").
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub servo_dynamics: std::collections::BTreeMap<String, super::ServoParamsEntry>,
    /// The calibrated readings' file (docs/identification.md, "Calibrated readings"), relative
    /// to this file; optional.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub calibration: Option<String>,
    /// Sliding friction coefficient of a foot on the ground (docs/models.md); optional.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub foot_friction: Option<f64>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyEntry {
    pub name: String,
    pub mass_kg: f64,
    /// Centre of mass in the body frame.
    pub com_m: [f64; 3],
    /// About the centre of mass, body axes: `[ixx, iyy, izz, ixy, ixz, iyz]`.
    pub inertia_kg_m2: [f64; 6],
    #[serde(default)]
    pub source: String,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointEntry {
    pub leg: Leg,
    pub kind: JointKind,
    pub parent: String,
    pub child: String,
    /// Joint frame origin in the parent frame at angle zero.
    pub origin_xyz_m: [f64; 3],
    /// Joint frame orientation in the parent frame, URDF roll-pitch-yaw: `Rz(y) Ry(p) Rx(r)`.
    pub origin_rpy_rad: [f64; 3],
    /// Rotation axis in the joint frame (normalised on load).
    pub axis: [f64; 3],
    pub limits_rad: [f64; 2],
    /// `mx28`, `mx64`, `generic` or `fixed`.
    pub actuation: ActuationEntry,
    /// Proportional stiffness of the actuator (N m / rad); required unless fixed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness_nm_per_rad: Option<f64>,
    /// Angle of a fixed joint (rad); defaults to 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fixed_angle_rad: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spring: Option<SpringEntry>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub servo: Option<ServoEntry>,
    /// This joint's servo dynamics, over its servo model's (`servo_dynamics = { ... }`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub servo_dynamics: Option<super::ServoParamsEntry>,
    #[serde(default)]
    pub source: String,
}

/// A joint's `actuation` field: a servo model's name ([`protocol::ServoModel::key`], e.g.
/// `"mx28"`), `"generic"` or `"fixed"`. The names of the servo models come from the dynamixel
/// crate, so a new model needs no change here.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum ActuationEntry {
    Servo(protocol::ServoModel),
    Generic,
    Fixed,
}

impl TryFrom<String> for ActuationEntry {
    type Error = String;

    fn try_from(name: String) -> Result<Self, String> {
        match name.as_str() {
            "generic" => Ok(Self::Generic),
            "fixed" => Ok(Self::Fixed),
            other => protocol::ServoModel::from_key(other)
                .map(Self::Servo)
                .ok_or_else(|| {
                    let servos: Vec<String> = protocol::ServoModel::ALL
                        .iter()
                        .map(|m| format!("\"{}\"", m.key()))
                        .collect();
                    format!(
                        "unknown actuation \"{other}\": expected a servo model ({}), \"generic\" or \"fixed\"",
                        servos.join(", ")
                    )
                }),
        }
    }
}

impl From<ActuationEntry> for String {
    fn from(entry: ActuationEntry) -> String {
        match entry {
            ActuationEntry::Servo(m) => m.key().to_owned(),
            ActuationEntry::Generic => "generic".to_owned(),
            ActuationEntry::Fixed => "fixed".to_owned(),
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ServoEntry {
    pub id: u8,
    pub zero_offset_rad: f64,
    pub sign: i8,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FootEntry {
    pub leg: Leg,
    pub body: String,
    pub point_m: [f64; 3],
    #[serde(default)]
    pub source: String,
}

/// Parses and validates a model from TOML text; `file` names it in errors.
pub fn from_toml_str(text: &str, file: &str) -> Result<Model, ModelError> {
    let mf: ModelFile = toml::from_str(text).map_err(|e| ModelError::Toml {
        file: file.to_string(),
        message: e.to_string(),
    })?;
    mf.to_model(file)
}

/// Reads and validates a model file.
pub fn load(path: &std::path::Path) -> Result<Model, ModelError> {
    let text = std::fs::read_to_string(path).map_err(|source| ModelError::Io {
        file: path.to_path_buf(),
        source,
    })?;
    from_toml_str(&text, &path.display().to_string())
}

fn finite3(v: &[f64; 3]) -> bool {
    v.iter().all(|x| x.is_finite())
}

impl ModelFile {
    /// The servo dynamics of the file: each `[servo_dynamics.NAME]` of a servo model's name,
    /// then each joint's own (ranges: [`Model::validate`]).
    fn servo_dynamics(&self, file: &str) -> Result<ServoDynamics, ModelError> {
        let mut d = ServoDynamics::default();
        for (key, entry) in &self.servo_dynamics {
            let servo = protocol::ServoModel::from_key(key).ok_or_else(|| {
                let known: Vec<&str> = protocol::ServoModel::ALL.iter().map(|m| m.key()).collect();
                field(
                    file,
                    "servo_dynamics",
                    key,
                    format!("unknown servo model (known: {})", known.join(", ")),
                )
            })?;
            d.set_model(servo, *entry);
        }
        for j in &self.joints {
            if let Some(entry) = &j.servo_dynamics {
                d.set_joint(&format!("{}_{}", j.leg.name(), j.kind.name()), *entry);
            }
        }
        Ok(d)
    }

    /// Converts to a [`Model`], checking every field.
    pub fn to_model(&self, file: &str) -> Result<Model, ModelError> {
        let mut bodies = Vec::with_capacity(self.bodies.len());
        let mut index = std::collections::HashMap::new();
        for b in &self.bodies {
            let place = format!("body {}", b.name);
            if index.insert(b.name.clone(), bodies.len()).is_some() {
                return Err(field(file, place, "name", "defined twice"));
            }
            if !(b.mass_kg.is_finite() && b.mass_kg >= 0.0) {
                return Err(field(
                    file,
                    place,
                    "mass_kg",
                    format!("{} is not a mass >= 0", b.mass_kg),
                ));
            }
            if !finite3(&b.com_m) {
                return Err(field(file, place, "com_m", "not finite"));
            }
            let [ixx, iyy, izz, ixy, ixz, iyz] = b.inertia_kg_m2;
            let inertia = Matrix3::new(ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz);
            let eig = inertia.symmetric_eigenvalues();
            let tol = 1e-12 * inertia.abs().max();
            if !inertia.iter().all(|x| x.is_finite()) || eig.iter().any(|&e| e < -tol) {
                return Err(field(
                    file,
                    place,
                    "inertia_kg_m2",
                    "not a positive semi-definite tensor",
                ));
            }
            bodies.push(Body {
                name: b.name.clone(),
                mass: b.mass_kg,
                com: Vector3::from(b.com_m),
                inertia,
            });
        }
        if bodies.first().map(|b| b.name.as_str()) != Some("thorax") {
            return Err(field(
                file,
                "body list",
                "body[0].name",
                "the first body must be `thorax`",
            ));
        }
        let mut joints = Vec::with_capacity(self.joints.len());
        let mut has_parent = vec![false; bodies.len()];
        has_parent[0] = true;
        for j in &self.joints {
            let name = format!("{}_{}", j.leg.name(), j.kind.name());
            let place = format!("joint {name}");
            let lookup = |n: &str, what: &'static str| {
                index.get(n).copied().ok_or_else(|| ModelError::Unknown {
                    file: file.to_string(),
                    place: place.clone(),
                    what,
                    name: n.to_string(),
                })
            };
            let parent = lookup(&j.parent, "parent body")?;
            let child = lookup(&j.child, "child body")?;
            if joints.iter().any(|o: &Joint| o.name == name) {
                return Err(field(
                    file,
                    &place,
                    "kind",
                    "this leg already has a joint of this kind",
                ));
            }
            if !has_parent[parent] {
                return Err(field(
                    file,
                    &place,
                    "parent",
                    "must be the thorax or the child of an earlier joint",
                ));
            }
            if child == 0 || has_parent[child] {
                return Err(field(
                    file,
                    &place,
                    "child",
                    "body already has a parent joint (or is the thorax)",
                ));
            }
            has_parent[child] = true;
            if !finite3(&j.origin_xyz_m) {
                return Err(field(file, &place, "origin_xyz_m", "not finite"));
            }
            if !finite3(&j.origin_rpy_rad) {
                return Err(field(file, &place, "origin_rpy_rad", "not finite"));
            }
            let axis = Vector3::from(j.axis);
            if !finite3(&j.axis) || axis.norm() < 1e-9 {
                return Err(field(
                    file,
                    &place,
                    "axis",
                    "must be a finite non-zero vector",
                ));
            }
            let [lo, hi] = j.limits_rad;
            if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
                return Err(field(
                    file,
                    &place,
                    "limits_rad",
                    format!("[{lo}, {hi}] is not an interval"),
                ));
            }
            let actuation = match j.actuation {
                ActuationEntry::Fixed => {
                    let angle = j.fixed_angle_rad.unwrap_or(0.0);
                    if !(lo..=hi).contains(&angle) {
                        return Err(field(
                            file,
                            &place,
                            "fixed_angle_rad",
                            format!("{angle} outside limits [{lo}, {hi}]"),
                        ));
                    }
                    Actuation::Fixed { angle }
                }
                ActuationEntry::Servo(_) | ActuationEntry::Generic => {
                    let stiffness = j.stiffness_nm_per_rad.ok_or_else(|| {
                        field(
                            file,
                            &place,
                            "stiffness_nm_per_rad",
                            "required for an actuated joint",
                        )
                    })?;
                    if !(stiffness.is_finite() && stiffness > 0.0) {
                        return Err(field(file, &place, "stiffness_nm_per_rad", "must be > 0"));
                    }
                    let actuator = match j.actuation {
                        ActuationEntry::Servo(m) => ActuatorKind::Servo(m),
                        ActuationEntry::Generic | ActuationEntry::Fixed => ActuatorKind::Generic,
                    };
                    Actuation::Actuated {
                        actuator,
                        stiffness,
                    }
                }
            };
            let spring = match j.spring {
                Some(s)
                    if !(s.stiffness_nm_per_rad.is_finite() && s.stiffness_nm_per_rad >= 0.0) =>
                {
                    return Err(field(
                        file,
                        &place,
                        "spring.stiffness_nm_per_rad",
                        "must be >= 0",
                    ));
                }
                Some(s) => Some(
                    super::spring::from_entry(&s, (lo, hi))
                        .map_err(|(f, why)| field(file, &place, f, why))?,
                ),
                None => None,
            };
            let servo = match (j.servo, &actuation) {
                (None, _) => None,
                (Some(_), Actuation::Fixed { .. }) => {
                    return Err(field(file, &place, "servo", "a fixed joint has no servo"));
                }
                (
                    Some(_),
                    Actuation::Actuated {
                        actuator: ActuatorKind::Generic,
                        ..
                    },
                ) => {
                    return Err(field(
                        file,
                        &place,
                        "servo",
                        "a generic actuator has no servo (name the servo model in actuation)",
                    ));
                }
                (
                    Some(s),
                    Actuation::Actuated {
                        actuator: ActuatorKind::Servo(servo_model),
                        ..
                    },
                ) => {
                    if s.id > 252 {
                        return Err(field(file, &place, "servo.id", format!("{} > 252", s.id)));
                    }
                    if s.sign != 1 && s.sign != -1 {
                        return Err(field(file, &place, "servo.sign", "must be 1 or -1"));
                    }
                    if joints
                        .iter()
                        .any(|o: &Joint| o.servo.map(|x| x.id) == Some(s.id))
                    {
                        return Err(field(
                            file,
                            &place,
                            "servo.id",
                            format!("ID {} used twice", s.id),
                        ));
                    }
                    Some(ServoMap {
                        id: s.id,
                        model: *servo_model,
                        zero_offset: s.zero_offset_rad,
                        sign: s.sign,
                    })
                }
            };
            let [r, p, y] = j.origin_rpy_rad;
            joints.push(Joint {
                name,
                leg: j.leg,
                kind: j.kind,
                parent,
                child,
                origin: Isometry3::from_parts(
                    Translation3::from(Vector3::from(j.origin_xyz_m)),
                    UnitQuaternion::from_rotation_matrix(&Rotation3::from_euler_angles(r, p, y)),
                ),
                axis: Unit::new_normalize(axis),
                limits: (lo, hi),
                actuation,
                spring,
                servo,
            });
        }
        if let Some(orphan) = has_parent.iter().position(|&p| !p) {
            return Err(field(
                file,
                format!("body {}", bodies[orphan].name),
                "name",
                "no joint has this body as child",
            ));
        }
        let mut feet = Vec::new();
        for f in &self.feet {
            let place = format!("foot {}", f.leg.name());
            let body = *index.get(&f.body).ok_or_else(|| ModelError::Unknown {
                file: file.to_string(),
                place: place.clone(),
                what: "body",
                name: f.body.clone(),
            })?;
            if feet.iter().any(|o: &Foot| o.leg == f.leg) {
                return Err(field(file, place, "leg", "two feet on one leg"));
            }
            if !finite3(&f.point_m) {
                return Err(field(file, place, "point_m", "not finite"));
            }
            feet.push(Foot {
                leg: f.leg,
                body,
                point: Vector3::from(f.point_m),
            });
        }
        let mut model = Model {
            name: self.name.clone(),
            bodies,
            joints,
            feet,
            gauges: Vec::new(),
            servo_dynamics: self.servo_dynamics(file)?,
            calibration: None,
            foot_friction: self.foot_friction,
        };
        model.validate(file)?;
        model.gauges = super::gauge_file::gauges_from_entries(&self.gauges, &model, file)?;
        if let Some(name) = &self.calibration {
            model.calibration = Some(super::calibration::load_named(name, file, &model)?);
        }
        Ok(model)
    }
}

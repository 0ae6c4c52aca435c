//! Writing a [`Model`] back out in the TOML model format, and the roll-pitch-yaw decomposition
//! shared with the URDF writer.

use super::file::{ActuationEntry, BodyEntry, FootEntry, JointEntry, ModelFile, ServoEntry};
use super::*;

/// Writes a model as TOML (sources left empty unless given per body / joint name).
pub fn to_toml_string(model: &Model, notes: &str, source: &dyn Fn(&str) -> String) -> String {
    let mf = ModelFile::from_model(model, notes, source);
    toml::to_string(&mf).expect("a ModelFile always serialises")
}

impl ModelFile {
    /// The file form of a model. `source` gives the source note of a body or joint by name.
    pub fn from_model(model: &Model, notes: &str, source: &dyn Fn(&str) -> String) -> ModelFile {
        let bodies = model
            .bodies
            .iter()
            .map(|b| {
                let i = b.inertia;
                BodyEntry {
                    name: b.name.clone(),
                    mass_kg: b.mass,
                    com_m: b.com.into(),
                    inertia_kg_m2: [
                        i[(0, 0)],
                        i[(1, 1)],
                        i[(2, 2)],
                        i[(0, 1)],
                        i[(0, 2)],
                        i[(1, 2)],
                    ],
                    source: source(&b.name),
                }
            })
            .collect();
        let joints = model
            .joints
            .iter()
            .map(|j| {
                let [r, p, y] = rpy_of(&j.origin.rotation);
                let (actuation, stiffness, fixed) = match &j.actuation {
                    Actuation::Fixed { angle } => (ActuationEntry::Fixed, None, Some(*angle)),
                    Actuation::Actuated {
                        actuator,
                        stiffness,
                    } => (
                        match actuator {
                            ActuatorKind::Servo(m) => ActuationEntry::Servo(*m),
                            ActuatorKind::Generic => ActuationEntry::Generic,
                        },
                        Some(*stiffness),
                        None,
                    ),
                };
                JointEntry {
                    leg: j.leg,
                    kind: j.kind,
                    parent: model.bodies[j.parent].name.clone(),
                    child: model.bodies[j.child].name.clone(),
                    origin_xyz_m: j.origin.translation.vector.into(),
                    origin_rpy_rad: [r, p, y],
                    axis: j.axis.into_inner().into(),
                    limits_rad: [j.limits.0, j.limits.1],
                    actuation,
                    stiffness_nm_per_rad: stiffness,
                    fixed_angle_rad: fixed,
                    spring: j.spring.map(|s| super::spring::to_entry(&s)),
                    servo: j.servo.map(|s| ServoEntry {
                        id: s.id,
                        zero_offset_rad: s.zero_offset,
                        sign: s.sign,
                    }),
                    servo_dynamics: model.servo_dynamics.of_joint(&j.name).copied(),
                    source: source(&j.name),
                }
            })
            .collect();
        let feet = model
            .feet
            .iter()
            .map(|f| FootEntry {
                leg: f.leg,
                body: model.bodies[f.body].name.clone(),
                point_m: f.point.into(),
                source: source(&format!("{}_foot", f.leg.name())),
            })
            .collect();
        let gauges = model
            .gauges
            .iter()
            .map(|g| super::GaugeEntry::from_gauge(g, model, source(&g.name)))
            .collect();
        ModelFile {
            name: model.name.clone(),
            notes: notes.to_string(),
            bodies,
            joints,
            feet,
            gauges,
            servo_dynamics: model
                .servo_dynamics
                .per_model
                .iter()
                .map(|(m, e)| (m.key().to_owned(), *e))
                .collect(),
            calibration: model
                .calibration
                .as_ref()
                .map(|c| c.path.display().to_string()),
            foot_friction: model.foot_friction,
        }
    }
}

/// Roll, pitch, yaw (URDF convention, `R = Rz(y) Ry(p) Rx(r)`) of a rotation, well conditioned at
/// pitch = +-90 degrees (where nalgebra's `euler_angles` loses about 1e-8 rad through `asin`, and
/// where roll and yaw are only defined together: yaw is then set to 0).
pub fn rpy_of(rot: &nalgebra::UnitQuaternion<f64>) -> [f64; 3] {
    let m = rot.to_rotation_matrix().into_inner();
    let cp = m[(0, 0)].hypot(m[(1, 0)]);
    let pitch = (-m[(2, 0)]).atan2(cp);
    if cp < 1e-10 {
        [(-m[(1, 2)]).atan2(m[(1, 1)]), pitch, 0.0]
    } else {
        [
            m[(2, 1)].atan2(m[(2, 2)]),
            pitch,
            m[(1, 0)].atan2(m[(0, 0)]),
        ]
    }
}

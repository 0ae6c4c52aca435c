//! The model data types shared by the planner (kinematics, dynamics) and the reports.

use nalgebra::{Isometry3, Matrix3, Unit, Vector3};
use serde::{Deserialize, Serialize};

/// A leg, named as in the paper: left/right, front/middle/hind.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Leg {
    LF,
    LM,
    LH,
    RF,
    RM,
    RH,
}

impl Leg {
    /// All six legs in the paper's order (left front to right hind).
    pub const ALL: [Leg; 6] = [Leg::LF, Leg::LM, Leg::LH, Leg::RF, Leg::RM, Leg::RH];

    /// +1 for a left leg, -1 for a right leg (REP-103: y points left).
    pub fn side(self) -> f64 {
        match self {
            Leg::LF | Leg::LM | Leg::LH => 1.0,
            Leg::RF | Leg::RM | Leg::RH => -1.0,
        }
    }

    /// Short name, e.g. `"LF"`.
    pub fn name(self) -> &'static str {
        match self {
            Leg::LF => "LF",
            Leg::LM => "LM",
            Leg::LH => "LH",
            Leg::RF => "RF",
            Leg::RM => "RM",
            Leg::RH => "RH",
        }
    }
}

/// A leg joint, named as in the paper.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum JointKind {
    /// Thorax-coxa protraction / retraction.
    ThC1,
    /// Thorax-coxa levation / depression.
    ThC2,
    /// Thorax-coxa rotation.
    ThC3,
    /// Coxa-trochanter flexion / extension.
    CTr,
    /// Trochanter-femur rotation (the paper's "TrF" on the robot).
    TrF1,
    /// Trochanter-femur flexion / extension.
    TrF2,
    /// Femur-tibia flexion / extension.
    FTi,
    /// Tibia-tarsus (fixed on both models).
    TiTar,
}

impl JointKind {
    /// The paper's name, e.g. `"ThC1"` (the second half of a joint's full name).
    pub fn name(self) -> &'static str {
        match self {
            JointKind::ThC1 => "ThC1",
            JointKind::ThC2 => "ThC2",
            JointKind::ThC3 => "ThC3",
            JointKind::CTr => "CTr",
            JointKind::TrF1 => "TrF1",
            JointKind::TrF2 => "TrF2",
            JointKind::FTi => "FTi",
            JointKind::TiTar => "TiTar",
        }
    }
}

impl std::fmt::Display for JointKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// What drives a joint.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Actuation {
    /// Driven by an actuator with a proportional controller of this stiffness (N m / rad).
    Actuated {
        actuator: ActuatorKind,
        stiffness: f64,
    },
    /// Locked at a fixed angle (rad); its moment about the axis is carried by the structure.
    Fixed { angle: f64 },
}

/// In words: `MX-28(2.0), stiffness 12.2 N m/rad` or `fixed at 10.0 deg`.
impl std::fmt::Display for Actuation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Actuation::Actuated {
                actuator,
                stiffness,
            } => write!(f, "{actuator}, stiffness {stiffness:.3e} N m/rad"),
            Actuation::Fixed { angle } => write!(f, "fixed at {:.1} deg", angle.to_degrees()),
        }
    }
}

/// What drives an actuated joint: a Dynamixel servo (its model says which) or a generic
/// actuator. Matched exhaustively; a new servo model is a new [`protocol::ServoModel`] variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum ActuatorKind {
    /// A Dynamixel servo of this model (stall torque, speed and tables from the dynamixel crate).
    Servo(protocol::ServoModel),
    /// A generic actuator (e.g. the fly's muscles) with no servo behind it.
    Generic,
}

impl ActuatorKind {
    /// The servo model behind the actuator; `None` for a generic actuator.
    pub fn servo(self) -> Option<protocol::ServoModel> {
        match self {
            Self::Servo(m) => Some(m),
            Self::Generic => None,
        }
    }
}

impl std::fmt::Display for ActuatorKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Servo(m) => write!(f, "{m}"),
            Self::Generic => f.write_str("generic actuator"),
        }
    }
}

impl From<protocol::ServoModel> for ActuatorKind {
    fn from(model: protocol::ServoModel) -> Self {
        Self::Servo(model)
    }
}

/// The servo model behind an actuator; a generic actuator (no servo) is given back as the error.
impl TryFrom<ActuatorKind> for protocol::ServoModel {
    type Error = ActuatorKind;

    fn try_from(kind: ActuatorKind) -> Result<Self, ActuatorKind> {
        kind.servo().ok_or(kind)
    }
}

/// A spring in parallel with a joint: torque = -stiffness (q - equilibrium). Its stiffness is
/// the parallel spring's alone; the joint's total stiffness adds the actuator's (see
/// [`crate::model::spring`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ParallelSpring {
    /// Parallel spring stiffness, N m / rad.
    pub stiffness: f64,
    /// rad. Until a plan resolves it, an [`EquilibriumSource::RestingPosture`] or
    /// [`EquilibriumSource::StepMidrange`] spring holds the middle of the joint's limits here.
    pub equilibrium: f64,
    /// Where `equilibrium` comes from.
    #[serde(default)]
    pub equilibrium_from: EquilibriumSource,
}

/// Where a parallel spring's equilibrium angle comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum EquilibriumSource {
    /// Given in the model (rad).
    #[default]
    Given,
    /// The joint's angle in the plan's resting posture (the default of `dbot plan --spring`).
    RestingPosture,
    /// The middle of the joint's range of motion over the planned step (paper section 2.2.1:
    /// "equilibrium angles ... using the full ROM over the step").
    StepMidrange,
    /// A proxy for the paper's "leg positions resembling those of a newly dead fly" (section
    /// 2.2.1), whose angles the paper does not list: the original solver's CTr at about -35 deg
    /// and FTi about 20 deg below its smallest angle over the step
    /// (`../shared/reference/solver.md`, "Parallel springs"), every other joint at the middle of
    /// its range over the step as [`EquilibriumSource::StepMidrange`]. See
    /// [`crate::model::spring::dead_fly_equilibrium`].
    DeadFly,
}

/// In words, as `--spring-equilibrium` and the usage guide name them.
impl std::fmt::Display for EquilibriumSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            EquilibriumSource::Given => "given in the model",
            EquilibriumSource::RestingPosture => "the resting posture",
            EquilibriumSource::StepMidrange => "the middle of the step's range",
            EquilibriumSource::DeadFly => "a dead fly's posture",
        })
    }
}

/// Where a joint's servo sits on the bus and how its ticks map to the joint angle:
/// `angle = sign * (ticks - 2048) * 2 pi / 4096 + zero_offset`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ServoMap {
    /// Dynamixel ID, 0..=252.
    pub id: u8,
    /// Servo model (the joint's actuator: the model file says it once, in `actuation`).
    pub model: protocol::ServoModel,
    /// Joint angle (rad) at the servo's centre position (2048 ticks).
    pub zero_offset: f64,
    /// +1 or -1: whether increasing ticks increase the joint angle.
    pub sign: i8,
}

impl ServoMap {
    /// The joint's angle <-> ticks converter, the project's one ([`protocol::Calibration`]):
    /// zero at the servo's centre (half a turn), turning with the map's sign. The joint angle is
    /// `zero_offset` plus the calibration's angle.
    pub fn centre_calibration(&self) -> protocol::Calibration {
        let sign = if self.sign < 0 {
            protocol::Sign::Negative
        } else {
            protocol::Sign::Positive
        };
        protocol::Calibration::new(self.model, self.model.ticks_per_rev() / 2, sign)
    }

    /// Servo position (ticks) at joint angle 0, unclamped: `centre - sign zero_offset tpr / 2 pi`,
    /// rounded half away from zero (to the microradian first, then to the tick).
    pub fn zero_ticks(&self) -> i64 {
        self.centre_calibration()
            .goal_of_urad(-(self.zero_offset * 1e6).round() as i64)
    }

    /// Joint angle (rad) of a servo position in ticks (wrapped to +-half a turn around the
    /// centre), to the microradian.
    pub fn angle_of_ticks(&self, ticks: i32) -> f64 {
        let c = self.centre_calibration();
        self.zero_offset + c.ticks_to_urad(c.joint_ticks(ticks)) as f64 * 1e-6
    }
}

/// A rigid body.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Body {
    pub name: String,
    /// kg.
    pub mass: f64,
    /// Centre of mass in the body's frame, m.
    pub com: Vector3<f64>,
    /// Inertia tensor about the centre of mass in the body's frame, kg m^2.
    pub inertia: Matrix3<f64>,
}

/// A hinge joint between a parent body and a child body.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Joint {
    /// Full name `<leg>_<joint>`, e.g. `LF_ThC1`.
    pub name: String,
    pub leg: Leg,
    pub kind: JointKind,
    /// Index of the parent body in [`Model::bodies`].
    pub parent: usize,
    /// Index of the child body; the child's frame is this joint's frame.
    pub child: usize,
    /// Pose of the joint frame in the parent's frame at angle zero.
    pub origin: Isometry3<f64>,
    /// Rotation axis in the joint frame.
    pub axis: Unit<Vector3<f64>>,
    /// Lower and upper angle limits, rad.
    pub limits: (f64, f64),
    pub actuation: Actuation,
    pub spring: Option<ParallelSpring>,
    pub servo: Option<ServoMap>,
}

/// A foot contact point on a leg's last body.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Foot {
    pub leg: Leg,
    /// Index of the body that carries the foot (the tarsus).
    pub body: usize,
    /// Contact point in that body's frame, m.
    pub point: Vector3<f64>,
}

/// A legged organism: bodies, joints (a tree rooted at body 0, the thorax) and feet.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Model {
    pub name: String,
    /// Body 0 is the thorax. Bodies rigidly attached to the thorax (head, abdomen, ballast) are
    /// either merged into it or hang from it on `Fixed` joints.
    pub bodies: Vec<Body>,
    /// Ordered so that a joint's parent body is the thorax or the child of an earlier joint.
    pub joints: Vec<Joint>,
    /// One foot per leg.
    pub feet: Vec<Foot>,
    /// Strain gauges on the leg segments ([`super::gauges`]); none unless the model file lists them.
    #[serde(default)]
    pub gauges: Vec<super::Gauge>,
    /// Servo dynamics the model file gives, per servo model and per joint
    /// ([`Model::servo_params`] resolves a joint's; docs/models.md, "Servo dynamics").
    #[serde(default)]
    pub servo_dynamics: super::ServoDynamics,
    /// The calibrated readings the model file names (`calibration = "cal.toml"`), if any:
    /// per joint the Present Load reading (over `servo_dynamics`'), per gauge its gain.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub calibration: Option<super::ReadingCalibration>,
    /// Sliding friction coefficient between a foot and the ground the model stands on, when the
    /// model file gives one (a fitted value: `lab::identify` from a walking trial); `None` is
    /// [`super::DEFAULT_FOOT_FRICTION`], an ESTIMATE ([`Model::foot_friction`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub foot_friction: Option<f64>,
}

impl Model {
    /// A model of these parts and nothing the model file adds: no strain gauges, the servos'
    /// e-manual dynamics, no calibration, the default foot friction (an AnimatLab import, a
    /// sub-model, a test's toy body).
    pub fn of_parts(name: String, bodies: Vec<Body>, joints: Vec<Joint>, feet: Vec<Foot>) -> Self {
        Self {
            name,
            bodies,
            joints,
            feet,
            gauges: Vec::new(),
            servo_dynamics: Default::default(),
            calibration: None,
            foot_friction: None,
        }
    }
}

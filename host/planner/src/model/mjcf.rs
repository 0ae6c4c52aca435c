//! MJCF export (MuJoCo's model format) of any model standing on a terrain: the body tree with the
//! model's masses, centres of mass and inertias; a hinge per actuated joint with its axis and limits
//! (fixed joints become rigid offsets at their angle); a 5 mm contact sphere per foot whose lowest
//! point is the foot tip in the stance; one position actuator per actuated joint (the servo's P
//! controller, see [`ServoActuator`]) and the servo's gear train on its hinge (`damping`,
//! `frictionloss`, `armature` from the model's servo dynamics, [`joint_actuator`]); parallel
//! springs; and the terrain.
//!
//! Pure text, no MuJoCo needed: the `physics` crate loads it, and its tests check that MuJoCo's own
//! model data equal the model's. Contact and solver settings are the ones measured to let a standing
//! robot tell the truth (../shared/reference/host-crates.md): stiff contact (solref 0.002 s, solimp
//! 0.999), elliptic cones, the feet's sliding friction the model's (`Model::foot_friction`,
//! 1.5 unless the model file gives it), no-slip iterations, 0.5 ms implicitfast steps.

use std::fmt::Write;

use super::{Actuation, ActuatorKind, Model, ServoParams};
use crate::kinematics;
use crate::terrain::{BallMount, Blocks, Ground, Terrain};
use nalgebra::{Isometry3, UnitQuaternion, Vector3};

/// Radius of the foot contact spheres, m.
pub const FOOT_RADIUS_M: f64 = 0.005;
/// Default simulation timestep, s (0.5 ms: steady stances to 1e-8 rad/s, host-crates.md).
pub const DEFAULT_TIMESTEP_S: f64 = 0.0005;
/// Mass of the free-spinning ball of the ball rig, kg. ESTIMATE: a light hollow sphere, as the
/// fly's foam ball is light against the fly; the rig's ball for the robot is not in the paper.
pub const BALL_MASS_KG: f64 = 0.2;

/// The world the model is placed in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Scene {
    /// Level ground (the planner's `flat`).
    Flat,
    /// Ground rising forward at this angle: the ground stays level in the file and gravity tilts,
    /// exactly as the planner's thorax frame sees an incline.
    Incline { angle_rad: f64 },
    /// A fixed ball (radius, centre in the stance's thorax frame); the robot is free on top of it.
    BallFixed { radius_m: f64, centre: [f64; 3] },
    /// The fly rig: the thorax is held in place and the ball spins freely under the feet.
    BallHeld { radius_m: f64, centre: [f64; 3] },
    /// Uneven ground: a field of blocks over a floor ([`write_blocks`]).
    Blocks(Blocks),
}

impl Scene {
    /// The scene for a planner terrain. A ball terrain needs the ball's centre in the stance
    /// (`Terrain::ball_centre` of the stance); `held` picks the fly rig over a fixed ball.
    pub fn from_terrain(terrain: &Terrain, ball_centre: Option<Vector3<f64>>, held: bool) -> Self {
        match *terrain {
            Terrain::Flat => Scene::Flat,
            Terrain::Incline { angle_rad } => Scene::Incline { angle_rad },
            Terrain::Ball { radius_m, .. } => {
                let c = ball_centre.unwrap_or_else(Vector3::zeros);
                let centre = [c.x, c.y, c.z];
                if held {
                    Scene::BallHeld { radius_m, centre }
                } else {
                    Scene::BallFixed { radius_m, centre }
                }
            }
        }
    }
}

/// The servo behind an actuated joint, as the position actuator models it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServoActuator {
    /// Stall torque, N m (the actuator's force limit).
    pub stall_nm: f64,
    /// Damping, N m s / rad: the slope of the DC motor's torque-speed line, stall torque over
    /// no-load speed, so that a saturated servo runs at most at its no-load speed.
    pub damping: f64,
    /// Rotor inertia seen at the output (armature), kg m^2. ESTIMATE (see [`servo_actuator`]).
    pub armature: f64,
    /// Viscous damping of the gear train, N m s/rad: the hinge's `damping`.
    pub viscous: f64,
    /// Coulomb friction of the gear train, N m: the hinge's `frictionloss`.
    pub friction: f64,
}

impl ServoActuator {
    /// The actuator of a servo with `params`: its torque-speed line (stall torque, and
    /// stall / no-load speed as the damping), armature, viscous damping and friction.
    pub fn of_params(params: &ServoParams) -> Self {
        Self {
            stall_nm: params.stall_torque_nm,
            damping: params.back_emf_nm_s_per_rad(),
            armature: params.armature_kg_m2,
            viscous: params.damping_nm_s_per_rad,
            friction: params.friction_nm,
        }
    }
}

/// The default actuator of an actuator family: a servo model's default servo dynamics
/// ([`ServoParams::defaults`]: stall torque, no-load speed and armature, an ESTIMATE, from the
/// dynamixel crate's [`dynamixel::ServoModel`]; no gear friction). A generic actuator (a fly's
/// muscles) gets no force limit and a light damping of 1 % of its stiffness per second.
pub fn servo_actuator(kind: ActuatorKind, stiffness: f64) -> ServoActuator {
    match kind {
        ActuatorKind::Servo(m) => ServoActuator::of_params(&ServoParams::defaults(m)),
        ActuatorKind::Generic => ServoActuator {
            stall_nm: f64::INFINITY,
            damping: 0.01 * stiffness,
            armature: 0.0,
            viscous: 0.0,
            friction: 0.0,
        },
    }
}

/// The actuator of model joint `j` (`None`: a fixed joint): its servo's resolved dynamics
/// ([`Model::servo_params`]: the model file's per-model and per-joint fields over the defaults),
/// or a generic actuator's ([`servo_actuator`]).
pub fn joint_actuator(model: &Model, j: usize) -> Option<ServoActuator> {
    let Actuation::Actuated {
        actuator,
        stiffness,
    } = model.joints.get(j)?.actuation
    else {
        return None;
    };
    Some(match model.servo_params(j) {
        Some(p) => ServoActuator::of_params(&p),
        None => servo_actuator(actuator, stiffness),
    })
}

/// MuJoCo's smallest mass and principal inertia of a moving body (its mjMINVAL). Smaller values
/// (the fly model's massless bridges, its segments' inertias in SI units) are raised to it by the
/// compiler's boundmass / boundinertia; Drosophibot II's values are all far above it.
pub const MUJOCO_FLOOR: f64 = 1e-15;

/// What to write besides the model.
#[derive(Debug, Clone, PartialEq)]
pub struct MjcfOptions {
    pub scene: Scene,
    /// The stance, one angle per model joint: the robot is placed so that its feet touch the
    /// ground in it (keyframe `stance`), and the foot spheres sit on the tips in it.
    pub stance_q: Vec<f64>,
    pub timestep_s: f64,
}

impl MjcfOptions {
    /// The planner's resting posture (table 1's body heights for the model) on `ground` (a
    /// ball held is the fly rig: thorax held, ball spinning; a fixed ball has the robot free on
    /// it; blocks stand in the flat posture), at the default timestep.
    pub fn stance(model: &Model, ground: &Ground) -> Result<Self, crate::plan::PlanError> {
        let params = crate::gait::StepParams::table1(&model.name);
        let terrain = ground.stance_terrain(params.ball_radius_m, params.ball_offset_m);
        let posture = kinematics::resting_posture(model, &terrain, &|leg| params.foot_goal(leg))?;
        let scene = match ground {
            Ground::Blocks(b) => Scene::Blocks(*b),
            Ground::Ball {
                mount: BallMount::Fixed,
                ..
            } => Scene::from_terrain(&terrain, posture.ball_centre, false),
            Ground::Flat | Ground::Incline { .. } | Ground::Ball { .. } => {
                Scene::from_terrain(&terrain, posture.ball_centre, true)
            }
        };
        Ok(Self {
            scene,
            stance_q: posture.q,
            timestep_s: DEFAULT_TIMESTEP_S,
        })
    }
}

fn v3(v: &Vector3<f64>) -> String {
    format!("{:e} {:e} {:e}", v.x, v.y, v.z)
}

fn quat(q: &UnitQuaternion<f64>) -> String {
    format!("{:e} {:e} {:e} {:e}", q.w, q.i, q.j, q.k)
}

fn pose(iso: &Isometry3<f64>) -> String {
    format!(
        r#"pos="{}" quat="{}""#,
        v3(&iso.translation.vector),
        quat(&iso.rotation)
    )
}

/// The model on `options.scene` as an MJCF document.
///
/// Names: bodies as in the model, hinges and their actuators as the model's joints
/// (`LF_ThC1`, ...), the thorax's free joint `root`, foot spheres `<leg>_foot`, the ground
/// `ground`, the ball `ball`. Actuators appear in the model's joint order, hinges in the body
/// tree's depth-first order ([`hinge_order`]).
pub fn to_mjcf(model: &Model, options: &MjcfOptions) -> String {
    let poses = kinematics::forward(model, &options.stance_q);
    let mut s = String::new();
    let gravity = match options.scene {
        Scene::Incline { angle_rad } => Terrain::Incline { angle_rad }.gravity(),
        _ => Terrain::Flat.gravity(),
    };
    let _ = writeln!(s, r#"<mujoco model="{}">"#, model.name);
    // fusestatic off: bodies on fixed joints stay bodies, so their masses can be checked.
    let _ = writeln!(
        s,
        r#"  <compiler angle="radian" autolimits="true" fusestatic="false" boundmass="{MUJOCO_FLOOR:e}" boundinertia="{MUJOCO_FLOOR:e}"/>"#
    );
    let _ = writeln!(
        s,
        r#"  <option timestep="{:e}" integrator="implicitfast" cone="elliptic" noslip_iterations="20" gravity="{}"/>"#,
        options.timestep_s,
        v3(&gravity)
    );
    // Only feet touch the terrain (contype 1 / conaffinity 2 against the terrain's 2 / 1).
    let _ = writeln!(
        s,
        r#"  <default><geom condim="3" friction="{} 0.005 0.0001" solref="0.002 1" solimp="0.999 0.999 0.001 0.5 2"/></default>"#,
        model.foot_friction()
    );
    s.push_str("  <worldbody>\n");
    let floor = match options.scene {
        Scene::Blocks(b) => b.floor_m(),
        Scene::Flat | Scene::Incline { .. } | Scene::BallFixed { .. } | Scene::BallHeld { .. } => {
            0.0
        }
    };
    let _ = writeln!(
        s,
        r#"    <geom name="ground" type="plane" size="0 0 0.05" pos="0 0 {floor:e}" contype="2" conaffinity="1"/>"#,
    );
    // Height of the thorax that puts the lowest foot tip on the ground.
    let lowest = poses.feet.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
    let (root, held) = match options.scene {
        Scene::Flat | Scene::Incline { .. } => (Vector3::new(0.0, 0.0, -lowest), false),
        Scene::Blocks(b) => (
            Vector3::new(0.0, 0.0, blocks_root_z(&b, &poses.feet)),
            false,
        ),
        Scene::BallFixed { radius_m, centre } | Scene::BallHeld { radius_m, centre } => {
            // The ball rests on the ground; the thorax sits where the stance puts it over it.
            let c = Vector3::from(centre);
            (Vector3::new(0.0, 0.0, radius_m - c.z), true)
        }
    };
    let held = held && matches!(options.scene, Scene::BallHeld { .. });
    let _ = writeln!(
        s,
        r#"    <body name="{}" pos="{}">"#,
        model.bodies[0].name,
        v3(&root)
    );
    if !held {
        s.push_str("      <freejoint name=\"root\"/>\n");
    }
    write_body(&mut s, model, &poses, 0, 3);
    s.push_str("    </body>\n");
    match options.scene {
        Scene::Flat | Scene::Incline { .. } => {}
        Scene::Blocks(b) => write_blocks(&mut s, &b),
        Scene::BallFixed { radius_m, centre } => {
            let c = Vector3::from(centre) + root;
            let _ = writeln!(
                s,
                r#"    <geom name="ball" type="sphere" size="{radius_m:e}" pos="{}" contype="2" conaffinity="1"/>"#,
                v3(&c)
            );
        }
        Scene::BallHeld { radius_m, centre } => {
            let c = Vector3::from(centre) + root;
            // A thin hollow sphere: I = 2/3 m r^2.
            let i = 2.0 / 3.0 * BALL_MASS_KG * radius_m * radius_m;
            let _ = writeln!(
                s,
                r#"    <body name="ball" pos="{}"><joint name="ball" type="ball" damping="1e-4"/><inertial pos="0 0 0" mass="{BALL_MASS_KG:e}" diaginertia="{i:e} {i:e} {i:e}"/><geom name="ball" type="sphere" size="{radius_m:e}" contype="2" conaffinity="1"/></body>"#,
                v3(&c)
            );
        }
    }
    s.push_str("  </worldbody>\n");
    write_actuators(&mut s, model);
    write_keyframe(&mut s, model, options, &root, held);
    s.push_str("</mujoco>\n");
    s
}

/// Thorax height that puts the highest-standing foot of the stance (`feet`, thorax frame) on the
/// block under it; the others hang until the body settles onto them.
fn blocks_root_z(b: &Blocks, feet: &[nalgebra::Point3<f64>]) -> f64 {
    feet.iter()
        .map(|p| b.height_at(p.x, p.y) - p.z)
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The blocks: one static box per cell from the floor to its top (none in a gap), named
/// `block_I_J`, touching the feet as the ground does.
fn write_blocks(s: &mut String, b: &Blocks) {
    let (_, ny) = b.cells_xy();
    let floor = b.floor_m();
    for (k, c) in b.cells().iter().enumerate() {
        let Some(top) = c.top_m else { continue };
        let half = b.size_m / 2.0;
        let hz = (top - floor) / 2.0;
        let _ = writeln!(
            s,
            r#"    <geom name="block_{}_{}" type="box" size="{half:e} {half:e} {hz:e}" pos="{:e} {:e} {:e}" contype="2" conaffinity="1"/>"#,
            k / ny,
            k % ny,
            c.centre_xy_m[0],
            c.centre_xy_m[1],
            floor + hz
        );
    }
}

/// Children of `body`, recursively, each with its inertial, its hinge and its foot sphere.
fn write_body(s: &mut String, model: &Model, poses: &kinematics::Poses, body: usize, depth: usize) {
    let ind = "  ".repeat(depth);
    let b = &model.bodies[body];
    // Principal axes, written as diaginertia + quat: MuJoCo's parser rejects a fullinertia whose
    // eigenvalues fall below its 1e-15 floor (the fly's segments), while a diagonal inertia is
    // raised to `boundinertia` by the compiler (see `MUJOCO_FLOOR`).
    let eig = nalgebra::SymmetricEigen::new(b.inertia);
    let mut axes = eig.eigenvectors;
    if axes.determinant() < 0.0 {
        axes.column_mut(2).neg_mut();
    }
    let rot = UnitQuaternion::from_matrix(&axes);
    let _ = writeln!(
        s,
        r#"{ind}<inertial pos="{}" quat="{}" mass="{:e}" diaginertia="{}"/>"#,
        v3(&b.com),
        quat(&rot),
        b.mass,
        v3(&eig.eigenvalues.map(|x| x.max(0.0)))
    );
    for f in model.feet.iter().filter(|f| f.body == body) {
        // Centre one radius above the tip, "above" as the stance's vertical seen from this body.
        let up = poses.bodies[body].rotation.inverse() * Vector3::z();
        let c = f.point + up * FOOT_RADIUS_M;
        let _ = writeln!(
            s,
            r#"{ind}<geom name="{}_foot" type="sphere" size="{FOOT_RADIUS_M:e}" pos="{}" contype="1" conaffinity="2" mass="0"/>"#,
            f.leg.name(),
            v3(&c)
        );
    }
    for (ji, j) in model
        .joints
        .iter()
        .enumerate()
        .filter(|(_, j)| j.parent == body)
    {
        match j.actuation {
            Actuation::Fixed { angle } => {
                let at = j.origin * UnitQuaternion::from_axis_angle(&j.axis, angle);
                let _ = writeln!(
                    s,
                    r#"{ind}<body name="{}" {}>"#,
                    model.bodies[j.child].name,
                    pose(&at)
                );
            }
            Actuation::Actuated { .. } => {
                let _ = writeln!(
                    s,
                    r#"{ind}<body name="{}" {}>"#,
                    model.bodies[j.child].name,
                    pose(&j.origin)
                );
                let servo = joint_actuator(model, ji).expect("an actuated joint has an actuator");
                let spring = j.spring.map_or(String::new(), |sp| {
                    format!(
                        r#" stiffness="{:e}" springref="{:e}""#,
                        sp.stiffness, sp.equilibrium
                    )
                });
                let _ = writeln!(
                    s,
                    r#"{ind}  <joint name="{}" type="hinge" axis="{}" range="{:e} {:e}" damping="{:e}" frictionloss="{:e}" armature="{:e}"{spring}/>"#,
                    j.name,
                    v3(&j.axis),
                    j.limits.0,
                    j.limits.1,
                    servo.viscous,
                    servo.friction,
                    servo.armature
                );
            }
        }
        write_body(s, model, poses, j.child, depth + 1);
        let _ = writeln!(s, "{ind}</body>");
    }
}

fn write_actuators(s: &mut String, model: &Model) {
    s.push_str("  <actuator>\n");
    for (ji, j) in model.joints.iter().enumerate() {
        let (Actuation::Actuated { stiffness, .. }, Some(servo)) =
            (&j.actuation, joint_actuator(model, ji))
        else {
            continue;
        };
        let stiffness = *stiffness;
        let limit = if servo.stall_nm.is_finite() {
            format!(
                r#" forcerange="{:e} {:e}""#,
                -servo.stall_nm, servo.stall_nm
            )
        } else {
            String::new()
        };
        let _ = writeln!(
            s,
            r#"    <position name="{0}" joint="{0}" kp="{1:e}" kv="{2:e}"{limit}/>"#,
            j.name, stiffness, servo.damping
        );
    }
    s.push_str("  </actuator>\n");
}

/// The actuated joints in the order MuJoCo numbers their hinges: depth-first through the body
/// tree, children in the model's joint order (the order [`to_mjcf`] writes them).
pub fn hinge_order(model: &Model) -> Vec<usize> {
    fn visit(model: &Model, body: usize, out: &mut Vec<usize>) {
        for (j, joint) in model.joints.iter().enumerate() {
            if joint.parent == body {
                if model.is_actuated(j) {
                    out.push(j);
                }
                visit(model, joint.child, out);
            }
        }
    }
    let mut out = Vec::new();
    visit(model, 0, &mut out);
    out
}

/// Keyframe `stance`: the stance's joint angles (qpos order: root, then the hinges in
/// [`hinge_order`], then the ball) and position goals (actuator order) equal to them.
fn write_keyframe(
    s: &mut String,
    model: &Model,
    options: &MjcfOptions,
    root: &Vector3<f64>,
    held: bool,
) {
    let mut qpos = Vec::new();
    if !held {
        qpos.extend([root.x, root.y, root.z, 1.0, 0.0, 0.0, 0.0]);
    }
    let ctrl: Vec<f64> = model
        .actuated_joints()
        .iter()
        .map(|&j| options.stance_q[j])
        .collect();
    qpos.extend(hinge_order(model).iter().map(|&j| options.stance_q[j]));
    if matches!(options.scene, Scene::BallHeld { .. }) {
        qpos.extend([1.0, 0.0, 0.0, 0.0]);
    }
    let list = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:e}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let _ = writeln!(
        s,
        r#"  <keyframe><key name="stance" qpos="{}" ctrl="{}"/></keyframe>"#,
        list(&qpos),
        list(&ctrl)
    );
}

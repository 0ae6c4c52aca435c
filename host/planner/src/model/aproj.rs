//! Importer for AnimatLab project files (.aproj), the original MATLAB solver's input.
//!
//! What the files hold and how it maps (checked against Drosobot2.aproj, see docs/models.md):
//! - Every number is a `ScaledNumber` with `Value` and a metric `Scale` prefix. Distances are metres
//!   times the prefix (a 10 cm femur is `Value="10" Scale="centi"`), whatever `DistanceUnits` says;
//!   masses are in `Environment/MassUnits` times the prefix. Angles are degrees.
//! - A child body's pose in its parent body's frame is `T(LocalPosition) Rx Ry Rz (Rotation)`; its
//!   `Joint` pose in the child body's frame is built the same way; a hinge turns about the joint
//!   frame's x axis. `EnableMotor` marks actuated joints; the others are fixed at angle 0.
//! - AnimatLab is y-up with z to the right; [`anim_to_rep`] is the one place that turns it into
//!   REP-103 (x forward, y left, z up). Our body frames are the joint frames.
//! - A leg's last body (`*_Tip`, tiny) becomes the foot point and its mass joins the tarsus.
//! - Inertia: AnimatLab bodies are boxes; we use the solid-box inertia of the box's dimensions
//!   about the centre of mass (an estimate: the real parts are not boxes).

use super::error::{ModelError, field};
use super::*;
use nalgebra::{Isometry3, Matrix3, Point3, Rotation3, Translation3, UnitQuaternion, Vector3};
use roxmltree::Node;

/// Options for [`import_aproj`]: what the .aproj does not say.
#[derive(Debug, Clone, PartialEq)]
pub struct ImportOptions {
    /// Model name; defaults to the organism's name.
    pub name: Option<String>,
    /// Stiffness given to every actuated joint (N m / rad); the .aproj has no actuator model.
    pub stiffness: f64,
}

impl Default for ImportOptions {
    fn default() -> Self {
        ImportOptions {
            name: None,
            stiffness: 1.0,
        }
    }
}

/// The rotation taking AnimatLab's y-up axes (x forward, y up, z right) to REP-103 (x forward,
/// y left, z up): x' = x, y' = -z, z' = y.
pub fn anim_to_rep() -> Rotation3<f64> {
    Rotation3::from_matrix_unchecked(Matrix3::new(1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0))
}

/// Reads an .aproj file.
pub fn import_aproj_file(
    path: &std::path::Path,
    opts: &ImportOptions,
) -> Result<Model, ModelError> {
    let text = std::fs::read_to_string(path).map_err(|source| ModelError::Io {
        file: path.to_path_buf(),
        source,
    })?;
    import_aproj(&text, &path.display().to_string(), opts)
}

struct Ctx<'a> {
    file: &'a str,
    mass_scale: f64,
}

fn prefix(scale: &str) -> Option<f64> {
    Some(match scale {
        "None" | "" => 1.0,
        "pico" => 1e-12,
        "nano" => 1e-9,
        "micro" => 1e-6,
        "milli" => 1e-3,
        "centi" => 1e-2,
        "Kilo" => 1e3,
        "Mega" => 1e6,
        "Giga" => 1e9,
        _ => return None,
    })
}

fn child<'a, 'i>(n: Node<'a, 'i>, tag: &str) -> Option<Node<'a, 'i>> {
    n.children().find(|c| c.has_tag_name(tag))
}

fn text_of(n: Node, tag: &str) -> Option<String> {
    child(n, tag)
        .and_then(|c| c.text())
        .map(|s| s.trim().to_string())
}

impl Ctx<'_> {
    fn scaled(&self, n: Node, place: &str, tag: &str) -> Result<f64, ModelError> {
        let missing = || field(self.file, place, tag, "missing or not a ScaledNumber");
        let value: f64 = n
            .attribute("Value")
            .ok_or_else(missing)?
            .parse()
            .map_err(|_| missing())?;
        let p = prefix(n.attribute("Scale").unwrap_or("None")).ok_or_else(|| {
            field(
                self.file,
                place,
                tag,
                format!("unknown Scale `{}`", n.attribute("Scale").unwrap_or("")),
            )
        })?;
        Ok(value * p)
    }
    fn number(&self, n: Node, place: &str, tag: &str) -> Result<f64, ModelError> {
        let c = child(n, tag).ok_or_else(|| field(self.file, place, tag, "missing"))?;
        self.scaled(c, place, tag)
    }
    fn vec3(&self, n: Node, place: &str, tag: &str) -> Result<Vector3<f64>, ModelError> {
        let c = child(n, tag).ok_or_else(|| field(self.file, place, tag, "missing"))?;
        let mut v = Vector3::zeros();
        for (i, k) in ["X", "Y", "Z"].iter().enumerate() {
            v[i] = self.number(c, place, k)?;
        }
        Ok(v)
    }
    /// `T(LocalPosition) Rx Ry Rz (Rotation, degrees)`.
    fn pose(&self, n: Node, place: &str) -> Result<Isometry3<f64>, ModelError> {
        let p = self.vec3(n, place, "LocalPosition")?;
        let e = self.vec3(n, place, "Rotation")?.map(f64::to_radians);
        let r = Rotation3::from_axis_angle(&Vector3::x_axis(), e.x)
            * Rotation3::from_axis_angle(&Vector3::y_axis(), e.y)
            * Rotation3::from_axis_angle(&Vector3::z_axis(), e.z);
        Ok(Isometry3::from_parts(
            Translation3::from(p),
            UnitQuaternion::from_rotation_matrix(&r),
        ))
    }
    /// Mass (kg), centre of mass (body frame) and box inertia about it (body axes).
    fn mass_props(
        &self,
        n: Node,
        place: &str,
    ) -> Result<(f64, Vector3<f64>, Matrix3<f64>), ModelError> {
        let m = self.number(n, place, "Mass")? * self.mass_scale;
        // Checked here to name the project's own field (the model check names the body's mass).
        if !(m.is_finite() && (0.0..=super::ranges::MAX_BODY_MASS_KG).contains(&m)) {
            return Err(field(
                self.file,
                place,
                "Mass",
                format!(
                    "{m} kg is not a mass in 0 ..= {} kg",
                    super::ranges::MAX_BODY_MASS_KG
                ),
            ));
        }
        let com = self.vec3(n, place, "COM")?;
        let length = |tag| -> Result<f64, ModelError> {
            let l = self.number(n, place, tag)?;
            if !(l.is_finite() && (0.0..=super::ranges::MAX_LENGTH_M).contains(&l)) {
                return Err(field(
                    self.file,
                    place,
                    tag,
                    format!(
                        "{l} m is not a box size in 0 ..= {} m",
                        super::ranges::MAX_LENGTH_M
                    ),
                ));
            }
            Ok(l)
        };
        let (lx, ly, lz) = (length("Length")?, length("Height")?, length("Width")?);
        let i = Matrix3::from_diagonal(&Vector3::new(
            ly * ly + lz * lz,
            lx * lx + lz * lz,
            lx * lx + ly * ly,
        )) * (m / 12.0);
        Ok((m, com, i))
    }
}

/// Splits an AnimatLab joint name (`LF_ThC1`, `RM_TrF`, `Right_Middle`, `LH_ThC`) into leg and kind.
pub fn parse_joint_name(name: &str) -> Option<(Leg, JointKind)> {
    let legs = [
        ("LF", Leg::LF),
        ("LM", Leg::LM),
        ("LH", Leg::LH),
        ("RF", Leg::RF),
        ("RM", Leg::RM),
        ("RH", Leg::RH),
    ];
    if let Some((side, pos)) = name.split_once('_') {
        let long = match (side, pos) {
            ("Left", "Front") => Some(Leg::LF),
            ("Left", "Middle") => Some(Leg::LM),
            ("Left", "Hind") => Some(Leg::LH),
            ("Right", "Front") => Some(Leg::RF),
            ("Right", "Middle") => Some(Leg::RM),
            ("Right", "Hind") => Some(Leg::RH),
            _ => None,
        };
        if let Some(leg) = long {
            // The robot's single fixed thorax-coxa mount of middle and hind legs.
            return Some((leg, JointKind::ThC1));
        }
        let leg = legs.iter().find(|(p, _)| *p == side)?.1;
        let kind = match pos {
            "ThC" | "ThC1" => JointKind::ThC1,
            "ThC2" => JointKind::ThC2,
            "ThC3" => JointKind::ThC3,
            "CTr" => JointKind::CTr,
            "TrF" | "TrF1" => JointKind::TrF1,
            "TrF2" => JointKind::TrF2,
            "FTi" => JointKind::FTi,
            "TiTar" => JointKind::TiTar,
            _ => return None,
        };
        return Some((leg, kind));
    }
    None
}

struct Raw {
    leg: Leg,
    kind: JointKind,
    depth: usize,
    order: usize,
    parent: String,
    body: Body,
    origin: Isometry3<f64>,
    limits: (f64, f64),
    actuated: bool,
    foot: Option<Vector3<f64>>,
}

/// Imports the first organism of an AnimatLab project.
pub fn import_aproj(text: &str, file: &str, opts: &ImportOptions) -> Result<Model, ModelError> {
    let doc = roxmltree::Document::parse(text).map_err(|e| ModelError::Xml {
        file: file.to_string(),
        message: e.to_string(),
    })?;
    let root = doc.root_element();
    let env = root
        .descendants()
        .find(|n| n.has_tag_name("Environment"))
        .ok_or_else(|| field(file, "project", "Environment", "missing"))?;
    let mass_units = text_of(env, "MassUnits").unwrap_or_else(|| "Grams".into());
    let mass_scale = match mass_units.as_str() {
        "Grams" => 1e-3,
        "Kilograms" => 1.0,
        "Milligrams" => 1e-6,
        other => {
            return Err(field(
                file,
                "Environment",
                "MassUnits",
                format!("unknown unit `{other}`"),
            ));
        }
    };
    let cx = Ctx { file, mass_scale };
    let organism = root
        .descendants()
        .find(|n| n.has_tag_name("Organism"))
        .ok_or_else(|| field(file, "project", "Organisms/Organism", "missing"))?;
    let org_name = text_of(organism, "Name").unwrap_or_default();
    let thorax_node = child(organism, "RigidBody")
        .ok_or_else(|| field(file, &org_name, "RigidBody", "missing root body"))?;
    let (tm, tcom, ti) = cx.mass_props(thorax_node, "body thorax")?;
    let c = anim_to_rep();
    let thorax = Body {
        name: "thorax".into(),
        mass: tm,
        com: c * tcom,
        inertia: c.matrix() * ti * c.matrix().transpose(),
    };
    // Our thorax frame expressed in the AnimatLab thorax body frame.
    let thorax_frame = Isometry3::from_parts(
        Translation3::identity(),
        UnitQuaternion::from_rotation_matrix(&c.inverse()),
    );
    let mut raws: Vec<Raw> = Vec::new();
    walk(&cx, thorax_node, "thorax", thorax_frame, 0, &mut raws)?;
    raws.sort_by_key(|r| (r.leg, r.depth, r.order));
    let mut bodies = vec![thorax];
    let mut joints = Vec::new();
    let mut feet = Vec::new();
    for r in raws {
        let parent = bodies
            .iter()
            .position(|b| b.name == r.parent)
            .ok_or_else(|| {
                field(
                    file,
                    format!("body {}", r.body.name),
                    "parent",
                    "parent body not imported",
                )
            })?;
        let child = bodies.len();
        let name = format!("{}_{}", r.leg.name(), r.kind.name());
        if joints.iter().any(|j: &Joint| j.name == name) {
            return Err(field(
                file,
                format!("joint {name}"),
                "Name",
                "two joints of one kind on one leg",
            ));
        }
        if let Some(p) = r.foot {
            feet.push(Foot {
                leg: r.leg,
                body: child,
                point: p,
            });
        }
        // A model file names each body once (its joints refer to bodies by name): two bodies of
        // one name would import, then write a model file that does not load (found by fuzzing).
        if bodies.iter().any(|b| b.name == r.body.name) {
            return Err(field(
                file,
                format!("body {}", r.body.name),
                "Name",
                "a second body of this name (body names must be unique)",
            ));
        }
        bodies.push(r.body);
        joints.push(Joint {
            name,
            leg: r.leg,
            kind: r.kind,
            parent,
            child,
            origin: r.origin,
            axis: Vector3::x_axis(),
            limits: r.limits,
            actuation: if r.actuated {
                Actuation::Actuated {
                    actuator: ActuatorKind::Generic,
                    stiffness: opts.stiffness,
                }
            } else {
                Actuation::Fixed { angle: 0.0 }
            },
            spring: None,
            servo: None,
        });
    }
    // AnimatLab has no strain gauges: add `[[gauge]]` entries to the written model file.
    let model = Model::of_parts(opts.name.clone().unwrap_or(org_name), bodies, joints, feet);
    model.validate(file)?;
    Ok(model)
}

/// Visits the children of `node`; `frame` is the parent's (our) frame in the parent's AnimatLab
/// body frame.
fn walk(
    cx: &Ctx,
    node: Node,
    parent: &str,
    frame: Isometry3<f64>,
    depth: usize,
    out: &mut Vec<Raw>,
) -> Result<(), ModelError> {
    let Some(children) = child(node, "ChildBodies") else {
        return Ok(());
    };
    for (order, b) in children
        .children()
        .filter(|n| n.has_tag_name("RigidBody"))
        .enumerate()
    {
        let bname = text_of(b, "Name").unwrap_or_default();
        let place = format!("body {bname}");
        let jn = child(b, "Joint")
            .ok_or_else(|| field(cx.file, &place, "Joint", "a child body without a joint"))?;
        let jname = text_of(jn, "Name").unwrap_or_default();
        let jplace = format!("joint {jname}");
        let body_pose = cx.pose(b, &place)?;
        let joint_in_body = cx.pose(jn, &jplace)?;
        let (m, com, inertia) = cx.mass_props(b, &place)?;
        let grandchildren: Vec<Node> = child(b, "ChildBodies")
            .map(|c| {
                c.children()
                    .filter(|n| n.has_tag_name("RigidBody"))
                    .collect()
            })
            .unwrap_or_default();
        let is_tip = grandchildren.is_empty() && bname.to_ascii_lowercase().ends_with("tip");
        if is_tip {
            // Merge into the parent (the last raw pushed for `parent`) as the foot point.
            let tip_in_parent = frame.inverse() * Point3::from(body_pose.translation.vector);
            let Some(last) = out.iter_mut().rev().find(|r| r.body.name == parent) else {
                return Err(field(cx.file, &place, "Name", "a tip on the thorax"));
            };
            merge_point_mass(&mut last.body, m, tip_in_parent.coords);
            last.foot = Some(tip_in_parent.coords);
            continue;
        }
        let (leg, kind) = parse_joint_name(&jname).ok_or_else(|| {
            field(
                cx.file,
                &jplace,
                "Name",
                "cannot tell leg and joint from the name (expected e.g. LF_CTr)",
            )
        })?;
        let lo = cx.number(child(jn, "LowerLimit").unwrap_or(jn), &jplace, "LimitPos");
        let hi = cx.number(child(jn, "UpperLimit").unwrap_or(jn), &jplace, "LimitPos");
        let limits = match (text_of(jn, "EnableLimits").as_deref(), lo, hi) {
            (Some("True"), Ok(lo), Ok(hi)) => (lo.to_radians(), hi.to_radians()),
            _ => (-std::f64::consts::PI, std::f64::consts::PI),
        };
        let own_frame = body_pose * joint_in_body;
        let origin = frame.inverse() * own_frame;
        let to_own = joint_in_body.inverse();
        let r = to_own.rotation.to_rotation_matrix();
        out.push(Raw {
            leg,
            kind,
            depth,
            order,
            parent: parent.to_string(),
            body: Body {
                name: bname.clone(),
                mass: m,
                com: (to_own * Point3::from(com)).coords,
                inertia: r.matrix() * inertia * r.matrix().transpose(),
            },
            origin,
            limits,
            actuated: text_of(jn, "EnableMotor").as_deref() == Some("True"),
            foot: None,
        });
        walk(cx, b, &bname, joint_in_body, depth + 1, out)?;
    }
    Ok(())
}

/// Adds a point mass `m` at `p` (body frame) to a body, keeping inertia about the new centre.
fn merge_point_mass(b: &mut Body, m: f64, p: Vector3<f64>) {
    let total = b.mass + m;
    if total <= 0.0 {
        return;
    }
    let com = (b.com * b.mass + p * m) / total;
    let shift = |mass: f64, d: Vector3<f64>| {
        (Matrix3::identity() * d.norm_squared() - d * d.transpose()) * mass
    };
    b.inertia += shift(b.mass, b.com - com) + shift(m, p - com);
    b.com = com;
    b.mass = total;
}

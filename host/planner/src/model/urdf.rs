//! URDF export: root link `thorax`, one link per body, joints named `<leg>_<joint>` (fixed ones as
//! `fixed`, posed at their fixed angle), a link `<leg>_tip` at each foot contact point; SI units.

use super::*;
use nalgebra::{Isometry3, UnitQuaternion};
use std::fmt::Write;

fn xyz_rpy(iso: &Isometry3<f64>) -> String {
    let t = iso.translation.vector;
    let [r, p, y] = super::file_write::rpy_of(&iso.rotation);
    format!(
        r#"<origin xyz="{:e} {:e} {:e}" rpy="{:e} {:e} {:e}"/>"#,
        t.x, t.y, t.z, r, p, y
    )
}

/// Effort limit (N m) written into the URDF: the servo's stall torque at 12 V
/// ([`protocol::ServoModel::stall_torque_nm`], from the Dynamixel e-manuals); 1 N m for a generic
/// actuator or a fixed joint.
fn effort(a: &Actuation) -> f64 {
    match a {
        Actuation::Actuated {
            actuator: ActuatorKind::Servo(m),
            ..
        } => f64::from(m.stall_torque_nm()),
        Actuation::Actuated {
            actuator: ActuatorKind::Generic,
            ..
        }
        | Actuation::Fixed { .. } => 1.0,
    }
}

/// The model as a URDF document.
pub fn to_urdf(model: &Model) -> String {
    let mut s = String::new();
    let _ = writeln!(s, r#"<?xml version="1.0"?>"#);
    let _ = writeln!(s, r#"<robot name="{}">"#, model.name);
    for b in &model.bodies {
        let i = b.inertia;
        let _ = writeln!(
            s,
            r#"  <link name="{}"><inertial><origin xyz="{:e} {:e} {:e}" rpy="0 0 0"/><mass value="{:e}"/><inertia ixx="{:e}" ixy="{:e}" ixz="{:e}" iyy="{:e}" iyz="{:e}" izz="{:e}"/></inertial></link>"#,
            b.name,
            b.com.x,
            b.com.y,
            b.com.z,
            b.mass,
            i[(0, 0)],
            i[(0, 1)],
            i[(0, 2)],
            i[(1, 1)],
            i[(1, 2)],
            i[(2, 2)]
        );
    }
    for j in &model.joints {
        let parent = &model.bodies[j.parent].name;
        let child = &model.bodies[j.child].name;
        let a = j.axis;
        match j.actuation {
            Actuation::Fixed { angle } => {
                let origin = j.origin * UnitQuaternion::from_axis_angle(&j.axis, angle);
                let _ = writeln!(
                    s,
                    r#"  <joint name="{}" type="fixed"><parent link="{parent}"/><child link="{child}"/>{}</joint>"#,
                    j.name,
                    xyz_rpy(&origin)
                );
            }
            Actuation::Actuated { .. } => {
                let _ = writeln!(
                    s,
                    r#"  <joint name="{}" type="revolute"><parent link="{parent}"/><child link="{child}"/>{}<axis xyz="{:e} {:e} {:e}"/><limit lower="{:e}" upper="{:e}" effort="{}" velocity="1.5"/></joint>"#,
                    j.name,
                    xyz_rpy(&j.origin),
                    a.x,
                    a.y,
                    a.z,
                    j.limits.0,
                    j.limits.1,
                    effort(&j.actuation)
                );
            }
        }
    }
    for f in &model.feet {
        let leg = f.leg.name();
        let _ = writeln!(s, r#"  <link name="{leg}_tip"/>"#);
        let _ = writeln!(
            s,
            r#"  <joint name="{leg}_tip_fixed" type="fixed"><parent link="{}"/><child link="{leg}_tip"/><origin xyz="{:e} {:e} {:e}" rpy="0 0 0"/></joint>"#,
            model.bodies[f.body].name, f.point.x, f.point.y, f.point.z
        );
    }
    s.push_str("</robot>\n");
    s
}

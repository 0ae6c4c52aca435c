//! The friction each [`Substrate`] stands for on the physics robot, and its hold on the plant:
//! the sliding friction coefficient mu of every contact between a foot sphere and the terrain
//! (MuJoCo slides a contact when its tangential force would exceed mu times its normal force).
//!
//! All four coefficients are ESTIMATES: nobody has measured them on the robot. The robot's tarsal
//! tips are silicone rubber (Dragon Skin 10) over an Onyx core, or Flexible 80A resin (the paper,
//! ../shared/paper/drosophibot-ii.txt); the numbers are the usual handbook ranges of dry friction
//! of a soft elastomer on each kind of surface, rounded, and sand paper is the MJCF's own contact
//! friction 1.5 (planner::model::to_mjcf, ../shared/reference/host-crates.md), the value with which
//! a standing robot's feet were measured not to creep, kept as the default scene's ground.

pub use board::substrate::{KNOWN, Substrate};

/// Sliding friction of a foot tip on sand paper: the MJCF's default contact friction. ESTIMATE:
/// elastomer on an abrasive paper grips at 1 or more; 1.5 is the exported model's value.
pub const SANDPAPER_MU: f64 = 1.5;
/// On an anti-slip (rubber) mat. ESTIMATE: rubber on rubber, handbook 1.0-1.2 dry.
pub const ANTI_SLIP_MAT_MU: f64 = 1.1;
/// On wire mesh. ESTIMATE: rubber on metal wires, handbook 0.6-0.9 dry (the tips touching
/// wires, not sinking into the mesh's openings).
pub const WIRE_MESH_MU: f64 = 0.7;
/// On the bare floor (a smooth, hard lab floor or table). ESTIMATE: elastomer on a smooth dry
/// hard surface, handbook 0.4-0.6 (lower once dusty).
pub const FLOOR_MU: f64 = 0.5;

/// The sliding friction coefficient of a foot tip on `substrate`; an unspecified one walks on the
/// default scene's ground (sand paper).
pub fn friction(substrate: Substrate) -> f64 {
    match substrate {
        Substrate::Unspecified | Substrate::Sandpaper => SANDPAPER_MU,
        Substrate::AntiSlipMat => ANTI_SLIP_MAT_MU,
        Substrate::WireMesh => WIRE_MESH_MU,
        Substrate::Floor => FLOOR_MU,
    }
}

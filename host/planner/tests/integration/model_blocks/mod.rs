//! The blocks of a model file (`[[body]]`, `[[joint]]`, `[[foot]]`) written from their numbers,
//! for the tests that build a small robot by hand: each block is the model file format's, field
//! for field, so the file the planner reads is the one the test's comments describe.
#![allow(dead_code)]

/// A `[[body]]`: mass in kg, centre of mass in m (body frame) and the principal moments of
/// inertia in kg m^2 (no products of inertia).
pub fn body(name: &str, mass_kg: f64, com_m: [f64; 3], inertia_kg_m2: [f64; 3]) -> String {
    let [ixx, iyy, izz] = inertia_kg_m2;
    format!(
        "[[body]]\nname = \"{name}\"\nmass_kg = {mass_kg:?}\ncom_m = {com_m:?}\n\
         inertia_kg_m2 = [{ixx:?}, {iyy:?}, {izz:?}, 0.0, 0.0, 0.0]\n"
    )
}

/// An actuated revolute `[[joint]]` of `leg`, `kind` from `parent` to `child`.
pub struct Joint<'a> {
    pub leg: &'a str,
    pub kind: &'a str,
    pub parent: &'a str,
    pub child: &'a str,
    /// The joint frame in the parent's, m and roll-pitch-yaw rad.
    pub origin_xyz_m: [f64; 3],
    pub origin_rpy_rad: [f64; 3],
    pub axis: [f64; 3],
    /// Symmetric limits, +- this, rad.
    pub limit_rad: f64,
    /// `mx28` or `mx64`.
    pub actuation: &'a str,
    pub stiffness_nm_per_rad: f64,
}

impl Joint<'_> {
    pub fn block(&self) -> String {
        let l = self.limit_rad;
        format!(
            "[[joint]]\nleg = \"{}\"\nkind = \"{}\"\nparent = \"{}\"\nchild = \"{}\"\n\
             origin_xyz_m = {:?}\norigin_rpy_rad = {:?}\naxis = {:?}\nlimits_rad = [{:?}, {l:?}]\n\
             actuation = \"{}\"\nstiffness_nm_per_rad = {:?}\n",
            self.leg,
            self.kind,
            self.parent,
            self.child,
            self.origin_xyz_m,
            self.origin_rpy_rad,
            self.axis,
            -l,
            self.actuation,
            self.stiffness_nm_per_rad
        )
    }
}

/// A `[[foot]]` of `leg` at `point_m` in `body`'s frame.
pub fn foot(leg: &str, body: &str, point_m: [f64; 3]) -> String {
    format!("[[foot]]\nleg = \"{leg}\"\nbody = \"{body}\"\npoint_m = {point_m:?}\n")
}

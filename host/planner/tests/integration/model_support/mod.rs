//! The smallest valid model file the model tests edit into broken ones: a thorax and one femur on
//! LF's CTr joint (an MX-64 at 30 N m/rad), with LF's foot on the femur.

pub const ONE_LEG: &str = r#"
name = "one-leg"
[[body]]
name = "thorax"
mass_kg = 1.0
com_m = [0.0, 0.0, 0.0]
inertia_kg_m2 = [1e-3, 1e-3, 1e-3, 0.0, 0.0, 0.0]
[[body]]
name = "femur"
mass_kg = 0.1
com_m = [0.05, 0.0, 0.0]
inertia_kg_m2 = [1e-5, 1e-4, 1e-4, 0.0, 0.0, 0.0]
[[joint]]
leg = "LF"
kind = "CTr"
parent = "thorax"
child = "femur"
origin_xyz_m = [0.1, 0.05, 0.0]
origin_rpy_rad = [0.0, 0.0, 0.0]
axis = [1.0, 0.0, 0.0]
limits_rad = [-1.0, 1.0]
actuation = "mx64"
stiffness_nm_per_rad = 30.0
[[foot]]
leg = "LF"
body = "femur"
point_m = [0.0, 0.1, 0.0]
"#;

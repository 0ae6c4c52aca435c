//! The perturbation platform on the physics robot: a box under one foot on a vertical slide
//! driven by a position actuator, and the servo that moves it, a servo of the bus at the
//! platform's ID like the joints' (../shared/reference/lab-practice.md). The body keeps only
//! the platform's geometry and its ESTIMATEs (ticks to height, the slide's stiffness): the
//! schedule (when the goal leaves rest, where to, for how long) is the firmware's alone
//! (`protocol::PlatformSetup::goal`, sent in the joints' Sync Write). Each bus cycle the slide's
//! command follows the servo's Goal Position ([`height_m`]) at its Profile Velocity
//! ([`speed_m_s`]), and the servo's Present Position is the slide's height
//! ([`ticks_at_height`]).
//!
//! Where the box stands: centred where the platform's leg's foot will stand when the platform
//! moves (the caller says, e.g. from a scouting walk: `lab::perturbation`); its top is level
//! with the ground at [`LEVEL_TICKS`].
//!
//! A `fall` goal lowers the box's top below the ground plane, where the plane still holds the foot:
//! only `rise` perturbs the physics robot (a hole in the ground is not modelled).

use std::fmt::Write;

/// Platform height per servo tick, m. ESTIMATE: the lab's linkage is not published; a 20 mm
/// servo horn, linearised (20 mm x 2 pi / 4096 per tick), so the lab's rise (2330 - 2020 = 310
/// ticks) lifts the top 9.5 mm.
pub const HEIGHT_PER_TICK_M: f64 = 0.020 * std::f64::consts::TAU / 4096.0;
/// The servo position at which the box's top is level with the ground, ticks: the lab's rest
/// position (`protocol::PlatformSetup::lab`, 2020), as the lab mounts its platform. ESTIMATE.
pub const LEVEL_TICKS: u16 = protocol::PlatformSetup::lab(protocol::PlatformMove::Rise, 0).rest;
/// The servo's Profile Velocity unit, rev/min (the MX e-manual's 0.229 rev/min).
pub const PROFILE_VELOCITY_RPM: f64 = 0.229;
/// Mass of the moving platform, kg. ESTIMATE: a 40 x 40 x 10 mm plate and its slide.
pub const PLATFORM_MASS_KG: f64 = 0.2;
/// Stiffness of the slide's position actuator, N/m, and its damping, N s/m (critical for
/// [`PLATFORM_MASS_KG`]): a 10 N foot load presses it 1 mm. ESTIMATE of a geared servo's hold.
pub const PLATFORM_KP_N_PER_M: f64 = 1.0e4;
pub const PLATFORM_KV_N_S_PER_M: f64 = 90.0;

/// The top's height above the ground at servo position `ticks`, m.
pub fn height_m(ticks: u32) -> f64 {
    (f64::from(ticks) - f64::from(LEVEL_TICKS)) * HEIGHT_PER_TICK_M
}

/// The servo position at the top's height `h_m` above the ground, ticks (the inverse of
/// [`height_m`], rounded; never below 0).
pub fn ticks_at_height(h_m: f64) -> u32 {
    (f64::from(LEVEL_TICKS) + h_m / HEIGHT_PER_TICK_M)
        .round()
        .max(0.0) as u32
}

/// The top's fastest travel at Profile Velocity `profile_velocity` (the register's unit,
/// [`PROFILE_VELOCITY_RPM`]), m/s; `None` for 0, as fast as the servo goes (here: the
/// actuator's own response).
pub fn speed_m_s(profile_velocity: u32) -> Option<f64> {
    let rev_s = f64::from(profile_velocity) * PROFILE_VELOCITY_RPM / 60.0;
    (profile_velocity > 0).then_some(rev_s * 4096.0 * HEIGHT_PER_TICK_M)
}

/// Half the platform's side and thickness, m.
const HALF_SIDE_M: f64 = 0.02;
const HALF_THICK_M: f64 = 0.005;

/// `xml` (an MJCF of [`planner::model::to_mjcf`]) with the platform centred under `foot_xy`:
/// body `platform` on slide `platform`, actuator `platform`, its box a terrain geom.
pub fn with_platform(xml: &str, foot_xy: [f64; 2]) -> String {
    let mut body = String::new();
    let _ = writeln!(
        body,
        r#"    <body name="platform" pos="{:e} {:e} {:e}"><joint name="platform" type="slide" axis="0 0 1" range="-0.03 0.03"/><inertial pos="0 0 0" mass="{PLATFORM_MASS_KG:e}" diaginertia="1e-4 1e-4 1e-4"/><geom name="platform" type="box" size="{HALF_SIDE_M:e} {HALF_SIDE_M:e} {HALF_THICK_M:e}" contype="2" conaffinity="1"/></body>"#,
        foot_xy[0], foot_xy[1], -HALF_THICK_M
    );
    let actuator = format!(
        r#"    <position name="platform" joint="platform" kp="{PLATFORM_KP_N_PER_M:e}" kv="{PLATFORM_KV_N_S_PER_M:e}"/>
"#
    );
    xml.replacen("  </worldbody>\n", &format!("{body}  </worldbody>\n"), 1)
        .replacen("  </actuator>\n", &format!("{actuator}  </actuator>\n"), 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heights_and_speeds_follow_the_servo_units() {
        // 310 ticks x 20 mm x 2 pi / 4096 = 9.51 mm.
        assert!((height_m(2330) - 9.5115e-3).abs() < 1e-6);
        assert_eq!(height_m(2020), 0.0);
        assert_eq!(ticks_at_height(9.5115e-3), 2330);
        // 240 x 0.229 rev/min = 0.916 rev/s = 3751.9 ticks/s = 115.1 mm/s.
        assert!((speed_m_s(240).unwrap() - 0.115109).abs() < 1e-5);
        assert_eq!(speed_m_s(0), None);
    }
}

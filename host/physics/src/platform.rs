//! The perturbation platform on the physics robot: a box under one foot, its top level with the
//! ground at rest, on a vertical slide joint driven by a position actuator, standing for the lab's
//! 23rd servo (ID 22) and its platform (../shared/reference/lab-practice.md). [`Platform`] is the
//! lab's schedule: at the start of the chosen step the servo's goal goes to `rise` (or `fall`),
//! `hold_cycles` bus cycles later back to `rest`; the goal moves at the profile velocity.
//!
//! Who writes the servo's goal: on a board the firmware, in the joints' Sync Write
//! (`protocol::PlatformSetup::goal`, the same schedule; `firmware::controller` platform). On the
//! physics robot the body still applies [`Platform::goal`] itself each bus cycle, from the
//! firmware's own playback position (the step and slice it plays), so the timing is the
//! firmware's; driving the box from the board's Sync Write goal for the platform's ID is NOT built
//! yet.
//!
//! A `fall` goal lowers the box's top below the ground plane, where the plane still holds the foot:
//! only `rise` perturbs the physics robot (a hole in the ground is not modelled).

use std::fmt::Write;

use planner::model::Leg;

/// Platform height per servo tick, m. ESTIMATE: the lab's linkage is not published; a 20 mm
/// servo horn, linearised (20 mm x 2 pi / 4096 per tick), so the lab's rise (2330 - 2020 = 310
/// ticks) lifts the top 9.5 mm.
pub const HEIGHT_PER_TICK_M: f64 = 0.020 * std::f64::consts::TAU / 4096.0;
/// The servo's Profile Velocity unit, rev/min (the MX e-manual's 0.229 rev/min).
pub const PROFILE_VELOCITY_RPM: f64 = 0.229;
/// Mass of the moving platform, kg. ESTIMATE: a 40 x 40 x 10 mm plate and its slide.
pub const PLATFORM_MASS_KG: f64 = 0.2;
/// Stiffness of the slide's position actuator, N/m, and its damping, N s/m (critical for
/// [`PLATFORM_MASS_KG`]): a 10 N foot load presses it 1 mm. ESTIMATE of a geared servo's hold.
pub const PLATFORM_KP_N_PER_M: f64 = 1.0e4;
pub const PLATFORM_KV_N_S_PER_M: f64 = 90.0;

/// Where the platform goes at the perturbed step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlatformMove {
    Rise,
    Fall,
}

/// The perturbation platform's servo and schedule (the lab's defaults: [`Platform::lab`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Platform {
    /// The leg whose foot stands on it.
    pub leg: Leg,
    /// The perturbed step, counted from 0 (the steps walked before it).
    pub step: u32,
    /// The platform servo's bus ID (22 on the lab's robot, after the joints' 0-21).
    pub servo_id: u8,
    /// Goal positions, ticks.
    pub rest: u16,
    pub rise: u16,
    pub fall: u16,
    pub moves: PlatformMove,
    /// Profile velocity, in the register's unit ([`PROFILE_VELOCITY_RPM`]); 0 is as fast as the
    /// servo goes, as on the MX (here: the actuator's own response).
    pub profile_velocity: u16,
    /// Bus cycles at the moved goal before it returns to rest (the lab's: 2).
    pub hold_cycles: u32,
}

impl Platform {
    /// The lab's platform under `leg`, rising at `step`: ID 22, rest 2020, rise 2330, fall 1570
    /// ticks, back to rest two cycles later. Profile velocity 240 (55 rev/min, about an MX-28's
    /// no-load speed, so as fast as the servo turns) is an ESTIMATE: the lab sets it before each
    /// trial and its value is not published.
    pub fn lab(leg: Leg, step: u32) -> Self {
        Self {
            leg,
            step,
            servo_id: 22,
            rest: 2020,
            rise: 2330,
            fall: 1570,
            moves: PlatformMove::Rise,
            profile_velocity: 240,
            hold_cycles: 2,
        }
    }

    /// The leg named `name` (`LF`, `LM`, `LH`, `RF`, `RM`, `RH`), for a platform under it.
    pub fn leg_named(name: &str) -> Result<Leg, String> {
        Leg::ALL
            .into_iter()
            .find(|l| l.name() == name)
            .ok_or_else(|| {
                format!(
                    "perturbation leg `{name}` is not a leg (legs: {})",
                    Leg::ALL.map(Leg::name).join(", ")
                )
            })
    }

    /// The goal at the moved position.
    pub fn moved_to(&self) -> u16 {
        match self.moves {
            PlatformMove::Rise => self.rise,
            PlatformMove::Fall => self.fall,
        }
    }

    /// The servo's goal in a bus cycle `cycles_in_step` cycles (0: the first) into the step
    /// after `steps_done` whole steps of a walk.
    pub fn goal(&self, steps_done: u32, cycles_in_step: u32) -> u16 {
        if steps_done == self.step && cycles_in_step < self.hold_cycles {
            self.moved_to()
        } else {
            self.rest
        }
    }

    /// The top's height above the ground at goal `ticks`, m.
    pub fn height_m(&self, ticks: u16) -> f64 {
        (f64::from(ticks) - f64::from(self.rest)) * HEIGHT_PER_TICK_M
    }

    /// The top's fastest travel, m/s (`None`: profile velocity 0, unlimited).
    pub fn speed_m_s(&self) -> Option<f64> {
        let rev_s = f64::from(self.profile_velocity) * PROFILE_VELOCITY_RPM / 60.0;
        (self.profile_velocity > 0).then_some(rev_s * 4096.0 * HEIGHT_PER_TICK_M)
    }
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
    fn the_lab_schedule_rises_for_two_cycles_at_the_chosen_step() {
        let p = Platform::lab(Leg::RM, 2);
        // Steps 0 and 1 and the third cycle of step 2 on: rest.
        assert_eq!(p.goal(1, 0), 2020);
        assert_eq!(p.goal(2, 0), 2330);
        assert_eq!(p.goal(2, 1), 2330);
        assert_eq!(p.goal(2, 2), 2020);
        assert_eq!(p.goal(3, 0), 2020);
        let fall = Platform {
            moves: PlatformMove::Fall,
            ..p
        };
        assert_eq!(fall.goal(2, 0), 1570);
    }

    #[test]
    fn heights_and_speeds_follow_the_servo_units() {
        let p = Platform::lab(Leg::LF, 0);
        // 310 ticks x 20 mm x 2 pi / 4096 = 9.51 mm.
        assert!((p.height_m(2330) - 9.5115e-3).abs() < 1e-6);
        // 240 x 0.229 rev/min = 0.916 rev/s = 3751.9 ticks/s = 115.1 mm/s.
        assert!((p.speed_m_s().unwrap() - 0.115109).abs() < 1e-5);
    }
}

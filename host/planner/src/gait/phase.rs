//! Gaits as phase offsets between legs.

use crate::model::Leg;
use serde::{Deserialize, Serialize};

/// Phase offsets as fractions of the step cycle: `phi_i` between neighbouring legs of one side
/// (hind leads, so the wave runs back to front), `phi_c` between a left leg and its right partner.
/// 0.5 / 0.5 is the tripod.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Gait {
    pub phi_i: f64,
    pub phi_c: f64,
}

impl Gait {
    pub const TRIPOD: Gait = Gait {
        phi_i: 0.5,
        phi_c: 0.5,
    };
    /// Diagonal pairs swing together: (LH, RM), (LM, RF), (LF, RH).
    pub const TETRAPOD: Gait = Gait {
        phi_i: 1.0 / 3.0,
        phi_c: 2.0 / 3.0,
    };
    /// One leg at a time.
    pub const WAVE: Gait = Gait {
        phi_i: 1.0 / 6.0,
        phi_c: 0.5,
    };

    /// `tripod`, `tetrapod`, `wave` or `PHI_I:PHI_C`.
    pub fn parse(s: &str) -> Option<Gait> {
        match s {
            "tripod" => Some(Gait::TRIPOD),
            "tetrapod" => Some(Gait::TETRAPOD),
            "wave" => Some(Gait::WAVE),
            _ => {
                let (a, b) = s.split_once(':')?;
                let g = Gait {
                    phi_i: a.trim().parse().ok()?,
                    phi_c: b.trim().parse().ok()?,
                };
                (g.phi_i.is_finite() && g.phi_c.is_finite()).then_some(g)
            }
        }
    }

    /// Where in the cycle a leg's own cycle (stance then swing) starts, in [0, 1).
    pub fn phase(&self, leg: Leg) -> f64 {
        let from_hind = match leg {
            Leg::LH | Leg::RH => 0.0,
            Leg::LM | Leg::RM => 1.0,
            Leg::LF | Leg::RF => 2.0,
        };
        let right = if leg.side() < 0.0 { self.phi_c } else { 0.0 };
        (from_hind * self.phi_i + right).rem_euclid(1.0)
    }
}

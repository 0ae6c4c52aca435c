//! [`Ground`]: the ground a user names, one typed value parsed in one place ([`Ground::parse`],
//! also `FromStr`) from the text every door takes: the planner's `terrain` parameter (CLI
//! `--terrain`, parameter files, plan.json), the physics robot's scene (`physics:SCENE`, the MJCF
//! export's `--scene`) and Python. It serializes as that same text, so plan.json files written
//! when the terrain was a string still read, and new ones read in old code.
//!
//! The planner plans for the terrains it can model ([`Ground::plan_terrain`]: flat, incline, the
//! fly rig's ball); the physics robot stands on any ground ([`Ground::stance_terrain`] gives the
//! terrain whose resting posture it stands in).

use std::fmt;
use std::str::FromStr;

use super::blocks::Blocks;
use super::{Terrain, TerrainError};

/// How the ball is mounted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BallMount {
    /// The fly rig: the thorax is held and the ball spins under the feet (`ball`).
    Held,
    /// A fixed ball, the robot free on top of it (`ball-fixed`).
    Fixed,
}

/// The ground under the robot, as named.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Ground {
    /// `flat`.
    Flat,
    /// `incline:DEG`: a plane rising forward.
    Incline { angle_deg: f64 },
    /// `ball[:R[:OFFSET]]` or `ball-fixed[:R[:OFFSET]]`, metres; a missing radius or offset is
    /// the model's (the stepping parameters' `ball_radius_m`, `ball_offset_m`).
    Ball {
        radius_m: Option<f64>,
        offset_m: Option<f64>,
        mount: BallMount,
    },
    /// `blocks[:SEED[:HEIGHT_M[:SIZE_M[:GAPS]]]]`: uneven ground (physics only).
    Blocks(Blocks),
}

/// The words of every parse error: what the text may be.
pub const GROUND_SYNTAX: &str = "flat, incline:DEG, ball[:RADIUS_M[:OFFSET_M]], \
     ball-fixed[:RADIUS_M[:OFFSET_M]] or blocks[:SEED[:HEIGHT_M[:SIZE_M[:GAPS]]]]";

impl Ground {
    /// `ball`: the fly rig with the model's ball.
    pub const BALL: Ground = Ground::Ball {
        radius_m: None,
        offset_m: None,
        mount: BallMount::Held,
    };

    /// Parses the text (see [`GROUND_SYNTAX`]).
    pub fn parse(text: &str) -> Result<Ground, TerrainError> {
        let err = |p: String| TerrainError {
            text: text.to_string(),
            problem: p,
            syntax: true,
        };
        let mut parts = text.split(':');
        let head = parts.next().unwrap_or("").trim();
        let fields: Vec<&str> = parts.collect();
        let num = |i: usize, what: &str| -> Result<Option<f64>, TerrainError> {
            match fields.get(i) {
                None => Ok(None),
                Some(s) => s
                    .trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .map(Some)
                    .ok_or_else(|| err(format!("{what} `{s}` is not a number"))),
            }
        };
        let at_most = |n: usize| {
            if fields.len() > n {
                Err(err("too many `:` fields".into()))
            } else {
                Ok(())
            }
        };
        let g = match head {
            "flat" => {
                at_most(0)?;
                Ground::Flat
            }
            "incline" => {
                at_most(1)?;
                let deg = num(0, "angle")?
                    .ok_or_else(|| err("incline needs an angle in degrees".into()))?;
                if deg.abs() >= 90.0 {
                    return Err(err("incline angle must be within (-90, 90) degrees".into()));
                }
                Ground::Incline { angle_deg: deg }
            }
            "ball" | "ball-fixed" => {
                at_most(2)?;
                let radius_m = num(0, "radius")?;
                if radius_m.is_some_and(|r| r <= 0.0) {
                    return Err(err("ball radius must be > 0".into()));
                }
                Ground::Ball {
                    radius_m,
                    offset_m: num(1, "offset")?,
                    mount: if head == "ball" {
                        BallMount::Held
                    } else {
                        BallMount::Fixed
                    },
                }
            }
            "blocks" => {
                at_most(4)?;
                let d = Blocks::DEFAULT;
                let seed = match fields.first() {
                    None => d.seed,
                    Some(s) => s
                        .trim()
                        .parse::<u64>()
                        .map_err(|_| err(format!("seed `{s}` is not a whole number >= 0")))?,
                };
                let b = Blocks {
                    seed,
                    max_height_m: num(1, "height")?.unwrap_or(d.max_height_m),
                    size_m: num(2, "size")?.unwrap_or(d.size_m),
                    gaps: num(3, "gaps")?.unwrap_or(d.gaps),
                };
                if !(0.0..=0.1).contains(&b.max_height_m) {
                    return Err(err("block height must be within [0, 0.1] m".into()));
                }
                if !(0.01..=0.5).contains(&b.size_m) {
                    return Err(err("block size must be within [0.01, 0.5] m".into()));
                }
                if !(0.0..1.0).contains(&b.gaps) {
                    return Err(err("gaps must be a fraction within [0, 1)".into()));
                }
                Ground::Blocks(b)
            }
            other => return Err(err(format!("unknown terrain `{other}`"))),
        };
        Ok(g)
    }

    /// The terrain the planner plans for: flat, an incline, or the fly rig's ball (a bare ball's
    /// radius and offset from `default_radius`, `default_offset`). A fixed ball and blocks are
    /// ground only the physics robot stands on: refused, saying so.
    pub fn plan_terrain(
        &self,
        default_radius: f64,
        default_offset: f64,
    ) -> Result<Terrain, TerrainError> {
        let refuse = |what: &str| TerrainError {
            text: self.to_string(),
            syntax: false,
            problem: format!(
                "the planner plans for flat, incline and the held ball only; {what} is a scene of \
                 the physics robot: plan for flat and walk the plan on `physics:{self}`"
            ),
        };
        match *self {
            Ground::Ball {
                mount: BallMount::Fixed,
                ..
            } => Err(refuse("a fixed ball")),
            Ground::Blocks(_) => Err(refuse("uneven ground (blocks)")),
            Ground::Flat | Ground::Incline { .. } | Ground::Ball { .. } => {
                Ok(self.stance_terrain(default_radius, default_offset))
            }
        }
    }

    /// The terrain whose resting posture the robot stands in on this ground: blocks stand in
    /// the flat posture, either ball mount in the ball's.
    pub fn stance_terrain(&self, default_radius: f64, default_offset: f64) -> Terrain {
        match *self {
            Ground::Flat | Ground::Blocks(_) => Terrain::Flat,
            Ground::Incline { angle_deg } => Terrain::Incline {
                angle_rad: angle_deg.to_radians(),
            },
            Ground::Ball {
                radius_m, offset_m, ..
            } => Terrain::Ball {
                radius_m: radius_m.unwrap_or(default_radius),
                offset_m: offset_m.unwrap_or(default_offset),
            },
        }
    }
}

impl fmt::Display for Ground {
    /// The text [`Ground::parse`] reads back to the same value.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Ground::Flat => write!(f, "flat"),
            Ground::Incline { angle_deg } => write!(f, "incline:{angle_deg}"),
            Ground::Ball {
                radius_m,
                offset_m,
                mount,
            } => {
                let head = match mount {
                    BallMount::Held => "ball",
                    BallMount::Fixed => "ball-fixed",
                };
                write!(f, "{head}")?;
                if let Some(r) = radius_m {
                    write!(f, ":{r}")?;
                    if let Some(o) = offset_m {
                        write!(f, ":{o}")?;
                    }
                }
                Ok(())
            }
            Ground::Blocks(b) => write!(
                f,
                "blocks:{}:{}:{}:{}",
                b.seed, b.max_height_m, b.size_m, b.gaps
            ),
        }
    }
}

impl FromStr for Ground {
    type Err = TerrainError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Ground::parse(s)
    }
}

impl serde::Serialize for Ground {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl<'de> serde::Deserialize<'de> for Ground {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let text = String::deserialize(d)?;
        Ground::parse(&text).map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_form_reads_back_from_its_text() {
        for text in [
            "flat",
            "incline:10",
            "incline:-7.5",
            "ball",
            "ball:0.3",
            "ball:0.3:0.05",
            "ball-fixed",
            "ball-fixed:0.5",
            "blocks:7:0.02:0.04:0.1",
        ] {
            let g = Ground::parse(text).unwrap();
            assert_eq!(g.to_string(), text);
            assert_eq!(Ground::parse(&g.to_string()).unwrap(), g);
        }
        assert_eq!(
            Ground::parse("blocks").unwrap(),
            Ground::Blocks(Blocks::DEFAULT)
        );
        assert_eq!(
            Ground::parse("blocks:3").unwrap(),
            Ground::Blocks(Blocks {
                seed: 3,
                ..Blocks::DEFAULT
            })
        );
    }

    #[test]
    fn bad_text_names_the_text_and_the_problem() {
        for (text, words) in [
            ("grass", "unknown terrain `grass`"),
            ("incline", "incline needs an angle"),
            ("incline:95", "within (-90, 90)"),
            ("incline:x", "angle `x` is not a number"),
            ("ball:-1", "radius must be > 0"),
            ("flat:1", "too many"),
            ("blocks:-1", "seed `-1` is not a whole number"),
            ("blocks:1:0.5", "block height"),
            ("blocks:1:0.01:0.05:1", "gaps must be"),
        ] {
            let e = Ground::parse(text).unwrap_err().to_string();
            assert!(e.contains(&format!("`{text}`")), "{e}");
            assert!(e.contains(words), "{text}: {e}");
        }
    }

    #[test]
    fn the_planner_refuses_what_it_cannot_plan_for_and_says_where_to_walk_it() {
        let e = Ground::parse("blocks:4")
            .unwrap()
            .plan_terrain(0.6, 0.7)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("plan for flat and walk the plan on `physics:blocks:4:"),
            "{e}"
        );
        assert!(
            Ground::parse("ball-fixed")
                .unwrap()
                .plan_terrain(0.6, 0.7)
                .is_err()
        );
        assert_eq!(
            Ground::parse("ball")
                .unwrap()
                .plan_terrain(0.6, 0.7)
                .unwrap(),
            Terrain::Ball {
                radius_m: 0.6,
                offset_m: 0.7
            }
        );
        let t = Ground::parse("incline:30")
            .unwrap()
            .plan_terrain(0.6, 0.7)
            .unwrap();
        let Terrain::Incline { angle_rad } = t else {
            panic!("not an incline")
        };
        assert!((angle_rad - std::f64::consts::PI / 6.0).abs() < 1e-15);
    }

    #[test]
    fn json_is_the_text_so_old_plan_files_read() {
        let g: Ground = serde_json::from_str(r#""ball:0.637""#).unwrap();
        assert_eq!(
            g,
            Ground::Ball {
                radius_m: Some(0.637),
                offset_m: None,
                mount: BallMount::Held
            }
        );
        assert_eq!(serde_json::to_string(&Ground::Flat).unwrap(), r#""flat""#);
        // The stepping parameters as plan.json holds them: `"terrain": "ball"`, as before.
        let mut p = crate::gait::StepParams::table1("drosophibot2");
        p.terrain = Ground::BALL;
        let v: serde_json::Value = serde_json::to_value(&p).unwrap();
        assert_eq!(v["terrain"], "ball");
        let back: crate::gait::StepParams = serde_json::from_value(v).unwrap();
        assert_eq!(back, p);
    }
}

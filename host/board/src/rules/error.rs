//! Why a rule refused, in the words every door shows, and the warning of an override.

use planner::plan::feasibility::Violation;

/// What a servo cannot do, one indented line per violation (joint, slice, margin).
#[derive(Debug, Clone, PartialEq)]
pub struct Violations(pub Vec<Violation>);

impl std::fmt::Display for Violations {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for (i, v) in self.0.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "  {v}")?;
        }
        Ok(())
    }
}

/// A refusal of a rule that protects the robot (or a failure of the work it guards).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RuleError {
    /// A servo cannot follow the plan or table (at its planned period).
    #[error(
        "{what}: the servos cannot follow this plan:\n{violations}\nplan a slower step (a longer swing: --swing, Python: swing_s=), or pass --allow-infeasible (Python: allow_infeasible=True) to build it anyway"
    )]
    Infeasible {
        what: String,
        violations: Violations,
    },
    /// A servo cannot follow the table at the period it was asked to play at.
    #[error(
        "{what}: at {period_s:.3} s per step ({scale:.3} times the planned {planned_s:.3} s) the servos cannot follow it:\n{violations}\nplay it at a longer period (steering: at a lower speed), or pass --allow-infeasible (Python: allow_infeasible=True) to play it anyway"
    )]
    TooFast {
        what: String,
        scale: f64,
        period_s: f64,
        planned_s: f64,
        violations: Violations,
    },
    /// Faster than planned, but the host does not hold the table to check it against the servos.
    #[error(
        "slot {slot}: playing it {scale:.3} times the planned period needs a check of its speeds against the servos, but this host does not hold its table (CRC {crc:#010x}; the board does not send tables back); play it at its planned period or slower, upload it from here first, or pass --allow-infeasible (Python: allow_infeasible=True) to play it anyway"
    )]
    UnknownTable { slot: u8, scale: f64, crc: u32 },
    /// Steering faster than planned, but this host did not set the steering family, so it does
    /// not know which tables to check.
    #[error(
        "steering at speed {speed}: faster than planned needs a check of the steering family's tables against the servos, but this host did not set the family; set it first (dbot steer --family, Python: Board.set_steer_family), steer at speed 1 or slower, or pass --allow-infeasible (Python: allow_infeasible=True) to steer anyway"
    )]
    UnknownFamily { speed: f64 },
    /// More slices than one gait slot of the board holds.
    #[error(
        "{what} {slices}: at most {max} slices per step fit a gait slot of the board ({capacity} bytes for {joints} joints, {per_slice} bytes per slice)"
    )]
    TooManySlices {
        what: String,
        slices: usize,
        max: usize,
        capacity: usize,
        joints: usize,
        per_slice: usize,
    },
    /// A stiffness the board or the servo's Position P Gain register cannot hold.
    #[error(transparent)]
    Stiffness(super::stiffness::StiffnessError),
    /// A baud change its servos did not follow (they keep their EEPROM baud): undone.
    #[error(
        "baud {to}: {who} did not answer at {to} bit/s, so the board is back at {from} bit/s (a servo keeps its own baud, the Baud Rate register in EEPROM, whatever the board's UART does); set every servo's baud first through a U2D2 (dbot dxl setup -p ADAPTER --id N --new-baud {to}; Python: dbot.Bench), then set the board's (dbot set --baud {to}; Python: Board.set_bus), which checks every servo answers",
        who = match joint { Some(j) => format!("the servo of joint {j}"), None => "a servo".to_owned() }
    )]
    BaudNotFollowed {
        from: u32,
        to: u32,
        joint: Option<u8>,
    },
    /// A baud change on a board with no joint map: no servos to check it with.
    #[error(
        "baud {baud}: the board has no joint map yet, so it cannot check that its servos answer at {baud} bit/s; upload and play a gait first (dbot upload, dbot run; Python: Board.upload_plan, Board.play)"
    )]
    BaudUnverifiable { baud: u32 },
    /// A per-joint setting on a board that has no joints yet.
    #[error("the board has no joint map yet (upload and play a gait first)")]
    NoJointMap,
    /// The board refused a per-joint setting.
    #[error("stiffness of joint {joint}: {source}")]
    JointSetting {
        joint: u8,
        source: crate::link::LinkError,
    },
    /// A joint of a step table whose stiffness its servo's P gain register cannot hold.
    #[error("{what}: joint {joint}: {source}")]
    TableStiffness {
        what: String,
        joint: String,
        source: super::stiffness::StiffnessError,
    },
    #[error(transparent)]
    PlanDir(#[from] planner::plan_dir::PlanDirError),
    #[error("{what}: {source}")]
    Table {
        what: String,
        source: planner::plan::table::TableError,
    },
    #[error("{what}: {source}")]
    BadTable {
        what: String,
        source: protocol::gait::TableError,
    },
    /// The host's copy of a table (a `virtual:PATH` robot's image) could not be read.
    #[error(transparent)]
    Image(#[from] crate::robot::ImageError),
    #[error(transparent)]
    Link(#[from] crate::link::LinkError),
}

/// What an override let through: the warning every door shows (`dbot` prefixes `warning: `,
/// Python raises it as a `UserWarning`).
#[derive(Debug, Clone, PartialEq)]
pub enum Overridden {
    /// A plan or table the servos cannot follow.
    Infeasible {
        what: String,
        violations: Violations,
    },
    /// A table played faster than planned whose speeds the host could not check.
    Unchecked { slot: u8, scale: f64, crc: u32 },
    /// Steering faster than planned over a family this host did not set (its tables unchecked).
    SteerUnchecked { speed: f64 },
}

impl std::fmt::Display for Overridden {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Infeasible { what, violations } => write!(
                f,
                "{what}: the servos cannot follow this plan (--allow-infeasible / allow_infeasible=True):\n{violations}"
            ),
            Self::Unchecked { slot, scale, crc } => write!(
                f,
                "slot {slot}: played at {scale:.3} times the planned period without a check of its speeds against the servos (this host does not hold its table, CRC {crc:#010x}; --allow-infeasible / allow_infeasible=True)"
            ),
            Self::SteerUnchecked { speed } => write!(
                f,
                "steering at speed {speed} without a check of the family's tables against the servos (this host did not set the family; --allow-infeasible / allow_infeasible=True)"
            ),
        }
    }
}

/// A plan directory's place in a message.
pub(crate) fn plan_dir_what(dir: &std::path::Path) -> String {
    format!("plan {}", dir.display())
}

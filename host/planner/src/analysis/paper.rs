//! The paper's robot-versus-fly comparison (section 3.1, tables S2 to S8) as data: the conditions,
//! what each table compares, and the counts the paper reports, so that ours can stand beside them.
//!
//! Conditions: Drosophibot II at a 4 s period (table 1: swing 1.6 s, duty 0.6; section 3.1 "the
//! modeled robot walked with a period of 4 s"). Scale-Drosophila at table 1's swing 0.1 s and duty
//! 0.6, a 0.25 s period: section 3.1 says the fly "walked with a period of 0.1 s", which is table
//! 1's swing duration, and table 1's caption says 0.275 s, which its own swing and duty do not give
//! (0.1 s / (1 - 0.6) = 0.25 s). Both organisms are quasi-static at these periods (inertial share
//! of the peak torque about 1 %, `dbot compare --swing`), so the choice moves the R^2 very little.

use super::{DofTrace, compare::ComparisonRow};
use crate::dynamics::CycleSolution;
use crate::model::Leg;
use crate::plan::Plan;

/// Robot swing duration of the comparison, s (period 4 s at duty 0.6).
pub const ROBOT_SWING_S: f64 = 1.6;
/// Fly swing duration of the comparison, s (table 1; period 0.25 s at duty 0.6).
pub const FLY_SWING_S: f64 = 0.1;

/// The tripod whose DoF the paper counts (front and hind of one side, middle of the other): 5
/// front (ThC1, ThC3, CTr, TrF, FTi) + 3 middle + 3 hind = 11 robot DoF.
pub const TRIPOD: [Leg; 3] = [Leg::LF, Leg::RM, Leg::LH];

/// Which trace a table compares.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    Angle,
    Torque,
}

/// A threshold count the paper reports: `count` of `of` DoF have R^2 above `above`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Claim {
    pub above: f64,
    pub count: usize,
    pub of: usize,
}

/// One supplementary table of the paper.
#[derive(Debug, Clone, PartialEq)]
pub struct PaperTable {
    pub id: &'static str,
    pub what: &'static str,
    pub quantity: Quantity,
    /// The paper's counts (section 3.1.1, 3.1.2, 3.2).
    pub claims: &'static [Claim],
    /// The paper's words, quoted.
    pub quote: &'static str,
}

/// Tables S2 to S8 and what the paper says about each. S4 to S6 are split here by spring case as
/// the text does ("tables S4-5" without springs; "table S4" flat and "table S6" ball with springs).
/// The paper states one claim for the torques of tables S4 and S5 (no parallel springs, flat and
/// ball): both tables are held to it.
const S4_S5_CLAIMS: &[Claim] = &[Claim {
    above: 0.9,
    count: 8,
    of: 11,
}];
const S4_S5_QUOTE: &str = "eight of the 11 DoF in this tripod have R-squared values over 0.9 while walking on either terrain (tables S4-5)";

pub const TABLES: [PaperTable; 8] = [
    PaperTable {
        id: "S2",
        what: "robot vs fly, flat, angles",
        quantity: Quantity::Angle,
        claims: &[
            Claim {
                above: 0.8,
                count: 10,
                of: 11,
            },
            Claim {
                above: 0.9,
                count: 6,
                of: 11,
            },
        ],
        quote: "10 of the 11 Drosophibot II DoF ... R-squared value greater than 0.8, six of which have values over 0.9",
    },
    PaperTable {
        id: "S3",
        what: "robot vs fly, ball, angles",
        quantity: Quantity::Angle,
        claims: &[
            Claim {
                above: 0.9,
                count: 8,
                of: 11,
            },
            Claim {
                above: 0.5,
                count: 11,
                of: 11,
            },
        ],
        quote: "eight of the 11 DoF have an R-squared value greater than 0.9 (the remaining three above 0.5)",
    },
    PaperTable {
        id: "S4",
        what: "robot vs fly, flat, torques, no parallel springs",
        quantity: Quantity::Torque,
        claims: S4_S5_CLAIMS,
        quote: S4_S5_QUOTE,
    },
    PaperTable {
        id: "S4 springs",
        what: "robot vs fly, flat, torques, parallel springs 1 and 3.8e-8 N m/rad",
        quantity: Quantity::Torque,
        claims: &[
            Claim {
                above: 0.7,
                count: 5,
                of: 11,
            },
            Claim {
                above: 0.5,
                count: 6,
                of: 11,
            },
        ],
        quote: "five of the 11 common DoF ... greater than 0.7, with six total having a value over 0.5 (table S4)",
    },
    PaperTable {
        id: "S5",
        what: "robot vs fly, ball, torques, no parallel springs",
        quantity: Quantity::Torque,
        claims: S4_S5_CLAIMS,
        quote: S4_S5_QUOTE,
    },
    PaperTable {
        id: "S6",
        what: "robot vs fly, ball, torques, parallel springs",
        quantity: Quantity::Torque,
        claims: &[Claim {
            above: 0.5,
            count: 5,
            of: 11,
        }],
        quote: "For the ball terrain, five common DoF have R-squared values over 0.5 (table S6)",
    },
    PaperTable {
        id: "S7",
        what: "fly flat vs fly ball, angles, parallel springs 3.8e-8 N m/rad",
        quantity: Quantity::Angle,
        claims: &[Claim {
            above: 0.7,
            count: 16,
            of: 18,
        }],
        quote: "16 of the 18 DoF with values greater than 0.7 (table S7)",
    },
    PaperTable {
        id: "S8",
        what: "fly flat vs fly ball, torques, parallel springs 3.8e-8 N m/rad",
        quantity: Quantity::Torque,
        claims: &[
            Claim {
                above: 0.7,
                count: 18,
                of: 18,
            },
            Claim {
                above: 0.9,
                count: 11,
                of: 18,
            },
        ],
        quote: "the R-squared values for the torques in each DoF across terrains are all greater than 0.7, with 11 of 18 greater than 0.9",
    },
];

/// DoF traces of a solved plan (angles and actuator torques per slice, model joint order).
pub fn traces(plan: &Plan, cycle: &CycleSolution) -> Vec<DofTrace> {
    plan.model
        .joints
        .iter()
        .enumerate()
        .map(|(j, joint)| {
            let angle: Vec<f64> = plan.q.iter().map(|q| q[j]).collect();
            let (lo, hi) = angle
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), a| {
                    (l.min(*a), h.max(*a))
                });
            DofTrace {
                leg: joint.leg,
                kind: joint.kind,
                mobile: hi - lo > 1e-9,
                angle,
                torque: cycle.slices.iter().map(|s| s.torque[j]).collect(),
            }
        })
        .collect()
}

/// The R^2 of the plain (not summed) DoF of `legs`.
pub fn r2_of(rows: &[ComparisonRow], legs: &[Leg], quantity: Quantity) -> Vec<f64> {
    rows.iter()
        .filter(|r| legs.contains(&r.leg) && r.summed_side.is_none())
        .filter_map(|r| match quantity {
            Quantity::Angle => r.r2_angle,
            Quantity::Torque => r.r2_torque,
        })
        .collect()
}

/// How many of `r2` lie above `above`.
pub fn count_above(r2: &[f64], above: f64) -> usize {
    r2.iter().filter(|&&r| r > above).count()
}

//! Every figure the host draws, reachable from the CLI and from Python without the CLI: plan plots
//! (joint angles, footfall, feet), the dynamics' torque and GRF plots, the predicted gauge strain, per-leg panels of
//! comparisons, the recording's plots and a perturbed leg's load per step. PNG via plotters with an embedded font.

mod bitmap;
pub mod dynamics;
pub mod legend;
pub mod legs;
pub mod paper_robot;
pub mod perturbation;
pub mod plan;
pub mod recording;
pub mod replay;
pub mod robot;
pub mod strain;
pub mod style;

/// What each file of a plan directory holds (columns, units, conventions): README.md beside them.
pub const PLAN_README: &str = include_str!("plan_readme.md");

pub use bitmap::Bitmap;

//! Every figure the host draws, reachable from the CLI and from Python without the CLI: plan plots
//! (joint angles, footfall, feet), the dynamics' torque and GRF plots, per-leg panels of
//! comparisons, and the recording's plots. PNG via plotters with an embedded font.

pub mod dynamics;
pub mod legs;
pub mod plan;
pub mod recording;
pub mod style;

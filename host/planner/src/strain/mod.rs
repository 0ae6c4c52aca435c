//! Predicted strain at the model's gauges from a solved plan (issue 26, item 2).
//!
//! Per slice and gauge: the internal wrench the distal part of the leg transmits across the
//! gauge's cross-section ([`cut`], from the distal free body, with an independent path from the
//! proximal joint), resolved into the gauge's reading by classical beam theory ([`section`]),
//! reported in microstrain ([`predict`]) and written as the tidy strain.csv ([`csv`]).

pub mod csv;
pub mod cut;
mod error;
pub mod predict;
pub mod section;

pub use error::StrainError;
pub use predict::{GaugeReading, StrainPrediction, predict, predict_plan, sites, slice_readings};
pub use section::{SectionProperties, SectionWrench, gauge_strain};

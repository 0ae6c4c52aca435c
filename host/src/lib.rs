//! The Drosophibot II host library: organism models, kinematics, inverse dynamics, gait planning,
//! reports and the link to the board. The `dbot` CLI is a thin layer over it.

pub mod analysis;
pub mod dynamics;
pub mod link;
pub mod model;
pub mod kinematics;
pub mod terrain;
pub mod gait;
pub mod plan;
pub mod report;
pub mod qp;
pub mod config;
pub mod record;
pub mod robot;

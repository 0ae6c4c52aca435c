//! The Drosophibot II host library: organism models, kinematics, inverse dynamics, gait planning,
//! reports and the link to the board. The `dbot` CLI is a thin layer over it.

pub mod analysis;
pub mod bus;
pub mod config;
pub mod dynamics;
pub mod files;
pub mod gait;
pub mod kinematics;
pub mod link;
pub mod model;
pub mod plan;
pub mod qp;
pub mod record;
pub mod report;
pub mod robot;
pub mod terrain;

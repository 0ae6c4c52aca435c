//! The integration tests of `planner`, one module per topic, linked into one test binary (one link
//! instead of one per file; nextest still runs each test in its own process).

// Helpers shared by several modules.
mod dynamics_support;
mod excitation;
mod foot_friction;
mod model_blocks;
mod model_support;
mod reliability_common;

mod calibration_file;
mod dynamics_analysis;
mod dynamics_balance;
mod dynamics_constraints;
mod dynamics_infeasible;
mod dynamics_kkt;
mod dynamics_rnea;
mod dynamics_scaling;
mod dynamics_static;
mod dynamics_table;
mod kinematics_fk;
mod model_gauges;
mod model_import;
mod model_validation;
mod parallel_spring;
mod plan_cycle;
mod plan_default_feasible;
mod plan_feasibility;
mod plan_ik_continuity;
mod plan_posture_presets;
mod qp_block;
mod reliability_inputs;
mod servo_calibration;
mod servo_dynamics;
mod strain_paths;
mod strain_section;
mod strain_standing;

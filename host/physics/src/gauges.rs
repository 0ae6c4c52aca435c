//! The model's strain gauges measured on the physics robot (issue 26 item 3), turned into
//! readings by the planner's own code (`planner::strain::slice_readings`), so a simulated and a
//! predicted reading differ only by what the two worlds differ in.
//!
//! What is measured in MuJoCo: every joint's angle, velocity and acceleration (`qpos`, `qvel`,
//! `qacc`), the thorax's motion (its free joint: world-frame linear velocity and acceleration of
//! its origin, body-frame angular ones), gravity as MuJoCo applies it now (it ramps in at power
//! on) and each foot sphere's contact force. The section wrench is then the distal free body's:
//! the cut segment's distal part and every body beyond it, their `m (a - g)` from that motion,
//! less the measured contact forces on their feet.
//!
//! Why this and not an MJCF split into welded bodies with a force-torque sensor at the section:
//! for rigid bodies the two are the same number. A weld sensor reports the interaction wrench of
//! the welded child with its parent, which MuJoCo itself computes (`mj_rnePostConstraint`) by
//! summing over the child's subtree exactly these `m (a - g)` and contact forces, from the same
//! `qacc`. The split would add bodies to the MJCF (merged beside other changes to it), and to
//! keep the segment's inertia exactly its two halves would need inertias that are not always
//! physical (a slender segment cut near its proximal end: `s I < m s (1 - s) L^2 / 4`), while the
//! segment's mass is shared out along its axis here exactly as in the planner (`cut.rs`: a
//! uniform rod), so the dynamics of the physics robot are untouched. The test below checks the
//! identity against MuJoCo's `cfrc_int` at every gauged segment's joint, to rounding.
//!
//! One simplification, kept because it is the planner's: a contact force acts at the model's
//! foot point, not at the foot sphere's touching point, which rolls off it by the sphere's radius
//! times the leg's turn since the stance (measured at most 1.3e-4 N m standing, of section
//! moments up to about 1 N m).

use std::collections::VecDeque;
use std::sync::Arc;

use mujoco_rs::prelude::MjtObjBase;
use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use planner::dynamics::{SliceInput, ThoraxMotion};
use planner::model::{Actuation, Model};
use planner::strain::cut::Site;
use planner::strain::{GaugeReading, StrainError};

use crate::plant::Plant;

/// How often the physics robot samples its gauges, s of simulated time: the strain board's
/// line period (a line of 36 values at 115200 bit/s and its 2 ms pause, ESTIMATE 24 ms).
pub const STRAIN_SAMPLE_S: f64 = 0.024;

/// Samples kept for [`StrainSampler::at`]: about 3 s, longer than a record waits in a queue.
const HISTORY: usize = 128;

/// The physics robot's gauges sampled every [`STRAIN_SAMPLE_S`] as it steps.
#[derive(Debug, Clone)]
pub(crate) struct StrainSampler {
    pub(crate) gauges: SimulatedGauges,
    /// The last [`HISTORY`] samples, oldest first.
    pub(crate) history: VecDeque<SimulatedStrain>,
    pub(crate) feed: Option<board::strain::source::Shared>,
    /// Per gauge its strain board column (None: a gauge the board does not have).
    columns: Vec<Option<usize>>,
}

impl StrainSampler {
    pub(crate) fn new(model: &Model, plant: &Plant) -> Result<Self, crate::PhysicsError> {
        let gauges = SimulatedGauges::new(model, plant).map_err(|e| crate::PhysicsError::Load {
            model: model.name.clone(),
            message: e.to_string(),
        })?;
        let columns = gauges
            .names()
            .iter()
            .map(|n| board::strain::Channel::parse(n).map(|c| c.column()))
            .collect();
        Ok(Self {
            gauges,
            history: VecDeque::with_capacity(HISTORY),
            feed: None,
            columns,
        })
    }

    /// Samples the gauges when a sample period has passed since the last one; whether it did.
    pub(crate) fn sample(&mut self, plant: &Plant) -> bool {
        let due = self
            .history
            .back()
            .is_none_or(|l| plant.time() - l.time_s >= STRAIN_SAMPLE_S - 1e-9);
        if !due || self.gauges.model.gauges.is_empty() {
            return false;
        }
        let s = self.gauges.read(plant);
        if let Some(feed) = &self.feed {
            let mut out = [0.0; board::strain::channels::CHANNELS];
            for (c, r) in self.columns.iter().zip(&s.readings) {
                if let Some(c) = c {
                    out[*c] = r.microstrain;
                }
            }
            feed.set(out);
        }
        if self.history.len() == HISTORY {
            self.history.pop_front();
        }
        self.history.push_back(s);
        true
    }

    /// The latest sample taken at or before `t_s` (None: none kept that old, or none yet).
    pub(crate) fn at(&self, t_s: f64) -> Option<&SimulatedStrain> {
        self.history.iter().rev().find(|s| s.time_s <= t_s + 1e-9)
    }
}

/// The gauges of one model on a plant of it.
#[derive(Debug, Clone)]
pub struct SimulatedGauges {
    model: Model,
    sites: Vec<Site>,
    /// Per model joint: its `qpos` and `dof` addresses (None: a fixed joint, at its angle).
    joints: Vec<Option<(usize, usize)>>,
    /// The thorax's free joint `dof` address (None: the thorax is held, as on the fly's rig).
    free_dof: Option<usize>,
    /// The gauges' names, `model.gauges` order.
    names: Arc<[String]>,
}

/// Every gauge's simulated reading at one instant.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulatedStrain {
    /// Simulated time, s.
    pub time_s: f64,
    /// Gauge names, `model.gauges` order (the strain board's for the built-in robot); shared
    /// by every sample of one set of gauges (36 names cloned for each sample, every 24 ms, were
    /// a tenth of the gauges' cost).
    pub names: Arc<[String]>,
    pub readings: Vec<GaugeReading>,
}

impl SimulatedStrain {
    /// Microstrain per gauge, in `names` order.
    pub fn microstrain(&self) -> Vec<f64> {
        self.readings.iter().map(|r| r.microstrain).collect()
    }
}

impl SimulatedGauges {
    /// The gauges of `model` on `plant` (a plant of `model`).
    pub fn new(model: &Model, plant: &Plant) -> Result<Self, StrainError> {
        let sites = planner::strain::sites(model)?;
        let mj = plant.data.model();
        let joints = model
            .joints
            .iter()
            .map(|j| match j.actuation {
                Actuation::Fixed { .. } => None,
                Actuation::Actuated { .. } => mj
                    .name_to_id(MjtObjBase::mjOBJ_JOINT, &j.name)
                    .map(|id| (mj.jnt_qposadr()[id] as usize, mj.jnt_dofadr()[id] as usize)),
            })
            .collect();
        let thorax = plant.thorax;
        let free_dof = (mj.body_jntnum()[thorax] > 0)
            .then(|| mj.jnt_dofadr()[mj.body_jntadr()[thorax] as usize] as usize);
        Ok(Self {
            model: model.clone(),
            sites,
            joints,
            free_dof,
            names: model.gauges.iter().map(|g| g.name.clone()).collect(),
        })
    }

    /// The gauges' names.
    pub fn names(&self) -> Vec<String> {
        self.names.to_vec()
    }

    /// The planner's slice input measured on `plant` now, and the contact force on each foot,
    /// both in the thorax frame.
    pub fn measured(&self, plant: &Plant) -> (SliceInput, Vec<Vector3<f64>>) {
        let d = &plant.data;
        let (qpos, qvel, qacc) = (d.qpos(), d.qvel(), d.qacc());
        let n = self.model.joints.len();
        let (mut q, mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        for (j, joint) in self.model.joints.iter().enumerate() {
            match (self.joints[j], &joint.actuation) {
                (Some((p, v)), _) => (q[j], qd[j], qdd[j]) = (qpos[p], qvel[v], qacc[v]),
                (None, Actuation::Fixed { angle }) => q[j] = *angle,
                (None, Actuation::Actuated { .. }) => {}
            }
        }
        let (_, w) = plant.thorax_pose();
        let r: Matrix3<f64> =
            UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w[0], w[1], w[2], w[3]))
                .to_rotation_matrix()
                .into_inner();
        let rt = r.transpose();
        let v3 = |s: &[f64]| Vector3::new(s[0], s[1], s[2]);
        let thorax = match self.free_dof {
            // A free joint: linear parts world frame, angular parts body frame (MuJoCo's rule).
            Some(f) => ThoraxMotion {
                linear_velocity: rt * v3(&qvel[f..f + 3]),
                angular_velocity: v3(&qvel[f + 3..f + 6]),
                linear_acceleration: rt * v3(&qacc[f..f + 3]),
                angular_acceleration: v3(&qacc[f + 3..f + 6]),
            },
            None => ThoraxMotion {
                linear_velocity: Vector3::zeros(),
                angular_velocity: Vector3::zeros(),
                linear_acceleration: Vector3::zeros(),
                angular_acceleration: Vector3::zeros(),
            },
        };
        let gravity = rt * Vector3::from(d.model().opt().gravity);
        let mut input = SliceInput::still(&self.model, q);
        input.qd = qd;
        input.qdd = qdd;
        input.thorax = thorax;
        input.gravity = gravity;
        let forces = plant.foot_forces();
        input.stance = forces.iter().map(|(_, f)| f[2] != 0.0).collect();
        let grf = forces.iter().map(|(_, f)| rt * Vector3::from(*f)).collect();
        (input, grf)
    }

    /// Every gauge's reading on `plant` now.
    pub fn read(&self, plant: &Plant) -> SimulatedStrain {
        let (input, grf) = self.measured(plant);
        SimulatedStrain {
            time_s: plant.time(),
            names: Arc::clone(&self.names),
            readings: planner::strain::slice_readings(&self.model, &self.sites, &input, &grf),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use planner::dynamics::{DynamicsOptions, solve_slice};
    use planner::strain::cut::{SliceBodies, distal_wrench};

    /// The sampler keeps the strain board's period and sets each gauge into its board column.
    #[test]
    fn the_sampler_feeds_each_gauge_into_its_board_column_every_24_ms() {
        use board::strain::StrainSource;
        let model = planner::model::builtin("drosophibot2").unwrap();
        let options =
            crate::PhysicsRobot::options(&model, &planner::terrain::Ground::Flat).unwrap();
        let mut plant = Plant::new(&model, &options).unwrap();
        for i in 0..plant.joints().len() {
            let j = plant.joints()[i].clone();
            plant.set_goal(i, options.stance_q[j.joint], true);
        }
        let mut s = StrainSampler::new(&model, &plant).unwrap();
        let mut feed = board::strain::source::Shared::default();
        s.feed = Some(feed.clone());
        plant.advance_to(1.2);
        s.sample(&plant);
        let first = s.history.back().cloned().unwrap();
        // 10 ms later: not due (24 ms), the sample stays.
        plant.advance_to(1.21);
        s.sample(&plant);
        assert_eq!(s.history.back().unwrap().time_s, first.time_s);
        plant.advance_to(1.225);
        s.sample(&plant);
        let latest = s.history.back().cloned().unwrap();
        assert!(latest.time_s > first.time_s);
        // A record of a time between the two samples gets the older one; before both, none.
        assert_eq!(s.at(first.time_s + 0.01).unwrap().time_s, first.time_s);
        assert_eq!(s.at(latest.time_s).unwrap().time_s, latest.time_s);
        assert!(s.at(first.time_s - 0.001).is_none());
        let board::strain::Reading::Microstrain(fed) = feed.reading(0, 0.0) else {
            panic!("the feed gives microstrain");
        };
        for (n, r) in latest.names.iter().zip(&latest.readings) {
            let c = board::strain::Channel::parse(n).unwrap().column();
            assert_eq!(fed[c], r.microstrain, "{n}");
        }
        assert!(
            fed.iter().any(|v| v.abs() > 50.0),
            "the standing legs are strained"
        );
    }

    /// The justification of the module header, checked: cut at a gauged segment's proximal end
    /// (position 0), the distal free body's wrench equals what MuJoCo's own recursive
    /// Newton-Euler (`mj_rnePostConstraint`: `cfrc_int`, the interaction of the segment with its
    /// parent, which a weld sensor there would report) says, for every gauged segment of the
    /// standing robot. Independent: MuJoCo sums its own bodies' inertia, motion and contacts.
    #[test]
    fn the_free_body_wrench_is_mujocos_interaction_wrench() {
        let model = planner::model::builtin("drosophibot2").unwrap();
        let options =
            crate::PhysicsRobot::options(&model, &planner::terrain::Ground::Flat).unwrap();
        let still = SliceInput::still(&model, options.stance_q.clone());
        let sol = solve_slice(&model, &still, &DynamicsOptions::default(), 0).unwrap();
        let mut plant = Plant::new(&model, &options).unwrap();
        for i in 0..plant.joints().len() {
            let j = plant.joints()[i].clone();
            plant.set_goal(
                i,
                options.stance_q[j.joint] + sol.torque[j.joint] / j.kp,
                true,
            );
        }
        plant.advance_to(1.5);
        // One consistent state: kinematics, contacts and qacc of now, then MuJoCo's RNE.
        plant.data.forward();
        plant.data.rne_post_constraint();
        let gauges = SimulatedGauges::new(&model, &plant).unwrap();
        let (input, grf) = gauges.measured(&plant);
        let bodies = SliceBodies::of(&model, &input);
        let (xt, w) = plant.thorax_pose();
        let r = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w[0], w[1], w[2], w[3]));
        let mj = plant.data.model();
        let weight = plant.weight_n();
        let (mut checked, mut worst, mut largest, mut worst_m) = (0, 0.0f64, 0.0f64, 0.0f64);
        for g in model.gauges.iter().filter(|g| g.position > 0.0) {
            let mut at_joint = g.clone();
            at_joint.position = 0.0;
            let site = Site::of(&model, &at_joint).unwrap();
            let frame = site.frame(&at_joint, &bodies.motions[site.segment]);
            let (f, m) = distal_wrench(&model, &site, &frame, &bodies, &grf);
            let b = mj
                .name_to_id(MjtObjBase::mjOBJ_BODY, &model.bodies[g.segment].name)
                .unwrap();
            let root = mj.body_rootid()[b] as usize;
            let c = Vector3::from(plant.data.subtree_com()[root]);
            let i = plant.data.cfrc_int()[b];
            let (torque_c, force) = (
                Vector3::new(i[0], i[1], i[2]),
                Vector3::new(i[3], i[4], i[5]),
            );
            let p = Vector3::from(xt) + r * frame.centroid;
            let mut moment_p = torque_c + (c - p).cross(&force);
            // Where the contact forces act: MuJoCo at the contact points, the free body at the
            // model's foot points. Moving each contact force to its foot point (world frame)
            // changes the ground's moment on the subtree by (foot - contact) x force, so the
            // parent's by (contact - foot) x force.
            for &foot in &site.feet {
                let geom = plant.feet[foot].1;
                let fp = &model.feet[foot];
                let bm = &bodies.motions[fp.body];
                let foot_w = Vector3::from(xt) + r * (bm.origin + bm.rotation * fp.point);
                for (k, con) in plant.data.contact().iter().enumerate() {
                    let sign = if con.geom[1] as usize == geom {
                        1.0
                    } else if con.geom[0] as usize == geom {
                        -1.0
                    } else {
                        continue;
                    };
                    let local = plant.data.contact_force(k);
                    let fw = Vector3::from_fn(|i, _| {
                        sign * (0..3)
                            .map(|row| local[row] * con.frame[3 * row + i])
                            .sum::<f64>()
                    });
                    moment_p += (Vector3::from(con.pos) - foot_w).cross(&fw);
                }
            }
            // MuJoCo's is the parent's wrench on the subtree; the section's, distal on proximal.
            let (fm, mm) = (-(r.inverse() * force), -(r.inverse() * moment_p));
            // The same sums of the same numbers once the contact forces act at the same points:
            // equal to rounding (measured 3e-15 N and 1e-15 N m), held to 1e-9 of the weight
            // (times 1 m for the moments).
            assert!(
                (f - fm).norm() < 1e-9 * weight,
                "{}: force {f} vs {fm}",
                g.name
            );
            let dm = (m - mm).norm();
            assert!(dm < 1e-9 * weight, "{}: moment off by {dm:e} N m", g.name);
            worst_m = worst_m.max(dm);
            worst = worst.max((f - fm).norm());
            largest = largest.max(fm.norm());
            checked += 1;
        }
        eprintln!(
            "free body vs cfrc_int: worst force difference {worst:.2e} N of up to {largest:.3} N, \
             worst moment difference {worst_m:.2e} N m"
        );
        assert_eq!(checked, 36);
        // Not a trivial agreement: the legs carry newtons.
        assert!(largest > 1.0, "{largest}");
    }
}

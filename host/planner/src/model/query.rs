//! Structural queries on a [`Model`]: leg chains, joint look-ups, default joint vectors.

use super::error::{ModelError, field};
use super::*;

impl Model {
    /// The servos on the bus as the model file says: `(id, servo model)` of every joint with a
    /// servo map, in joint order. The one list a virtual servo chain or a test rig is built from.
    pub fn servo_chain(&self) -> Vec<(u8, protocol::ServoModel)> {
        self.joints
            .iter()
            .filter_map(|j| j.servo.map(|s| (s.id, s.model)))
            .collect()
    }

    /// Index of the joint whose child is `body` (None for the thorax).
    pub fn parent_joint(&self, body: usize) -> Option<usize> {
        self.joints.iter().position(|j| j.child == body)
    }

    /// Index of a joint by its full name (e.g. `LF_ThC1`).
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }

    /// The foot of a leg, if the model has one.
    pub fn foot(&self, leg: Leg) -> Option<&Foot> {
        self.feet.iter().find(|f| f.leg == leg)
    }

    /// Joints from the thorax to the foot of `leg`, proximal first (fixed ones included).
    pub fn leg_chain(&self, leg: Leg) -> Vec<usize> {
        let Some(foot) = self.foot(leg) else {
            return Vec::new();
        };
        let mut chain = Vec::new();
        let mut body = foot.body;
        while let Some(j) = self.parent_joint(body) {
            chain.push(j);
            body = self.joints[j].parent;
        }
        chain.reverse();
        chain
    }

    /// The legs that have a foot, in [`Leg::ALL`] order.
    pub fn legs(&self) -> Vec<Leg> {
        Leg::ALL
            .into_iter()
            .filter(|l| self.foot(*l).is_some())
            .collect()
    }

    /// True if the joint is driven (not fixed).
    pub fn is_actuated(&self, joint: usize) -> bool {
        matches!(self.joints[joint].actuation, Actuation::Actuated { .. })
    }

    /// Indices of the actuated joints in model order.
    pub fn actuated_joints(&self) -> Vec<usize> {
        (0..self.joints.len())
            .filter(|&j| self.is_actuated(j))
            .collect()
    }

    /// A joint vector with fixed joints at their angle and actuated joints at mid-range.
    pub fn mid_range_q(&self) -> Vec<f64> {
        self.joints
            .iter()
            .map(|j| match j.actuation {
                Actuation::Fixed { angle } => angle,
                Actuation::Actuated { .. } => 0.5 * (j.limits.0 + j.limits.1),
            })
            .collect()
    }

    /// Total mass, kg.
    pub fn total_mass(&self) -> f64 {
        self.bodies.iter().map(|b| b.mass).sum()
    }

    /// Sum of the distances from joint to joint to the foot along a leg at the zero pose (m): the
    /// length scale for kinematic tolerances.
    pub fn leg_length(&self, leg: Leg) -> f64 {
        let chain = self.leg_chain(leg);
        let mut len = 0.0;
        for &j in chain.iter().skip(1) {
            len += self.joints[j].origin.translation.vector.norm();
        }
        len + self.foot(leg).map_or(0.0, |f| f.point.norm())
    }

    /// Checks that every foot hangs from the thorax through joints of its own leg only.
    pub(crate) fn check_legs(&self, file: &str) -> Result<(), ModelError> {
        for foot in &self.feet {
            let chain = self.leg_chain(foot.leg);
            let place = format!("foot {}", foot.leg.name());
            let root = chain.first().map_or(foot.body, |&j| self.joints[j].parent);
            if root != 0 {
                return Err(field(file, place, "body", "not connected to the thorax"));
            }
            if let Some(&j) = chain.iter().find(|&&j| self.joints[j].leg != foot.leg) {
                return Err(field(
                    file,
                    place,
                    "body",
                    format!(
                        "its chain passes joint {} of another leg",
                        self.joints[j].name
                    ),
                ));
            }
            if chain.len() > super::MAX_CHAIN {
                return Err(field(
                    file,
                    place,
                    "body",
                    format!(
                        "chain of {} joints; at most {} supported",
                        chain.len(),
                        super::MAX_CHAIN
                    ),
                ));
            }
        }
        Ok(())
    }
}

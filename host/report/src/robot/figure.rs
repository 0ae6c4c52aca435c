//! A stick figure of the robot in one pose: the thorax outline through the legs' first joints,
//! one segment per joint of each leg, the joints as dots and the feet marked stance or swing.
//! Built from the pose of every body, so a planned posture (forward kinematics) and a simulated
//! body (MuJoCo's world poses, mapped to the model's bodies) draw the same way.

use nalgebra::{Isometry3, Point3};

use planner::kinematics::forward;
use planner::model::{Leg, Model};

/// Which part of the robot a segment belongs to (its colour in the drawing).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Part {
    Thorax,
    LeftLeg,
    RightLeg,
}

/// One straight segment of the figure, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bone {
    pub from: Point3<f64>,
    pub to: Point3<f64>,
    pub part: Part,
}

/// A foot contact point and whether the foot is on the ground.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FootMark {
    pub leg: Leg,
    pub at: Point3<f64>,
    pub stance: bool,
}

/// The robot in one pose, in one frame (the thorax frame of a plan or the world of a simulation).
#[derive(Debug, Clone, PartialEq)]
pub struct StickFigure {
    pub bones: Vec<Bone>,
    /// Every joint origin (model joint order).
    pub joints: Vec<Point3<f64>>,
    /// One mark per foot ([`Model::feet`] order).
    pub feet: Vec<FootMark>,
}

/// A pose that does not fit the model.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FigureError {
    #[error("model {model}: {got} body poses given, the model has {expected} bodies")]
    BodyCount {
        model: String,
        expected: usize,
        got: usize,
    },
    #[error("model {model}: {got} stance flags given, the model has {expected} feet")]
    StanceCount {
        model: String,
        expected: usize,
        got: usize,
    },
    #[error("drawing {path}: {reason}")]
    Draw { path: String, reason: String },
}

fn part_of(leg: Leg) -> Part {
    if leg.side() < 0.0 {
        Part::RightLeg
    } else {
        Part::LeftLeg
    }
}

impl StickFigure {
    /// The figure of `model` with body `b` at pose `bodies[b]` ([`Model::bodies`] order) and foot
    /// `f` in stance when `stance[f]` ([`Model::feet`] order).
    pub fn from_bodies(
        model: &Model,
        bodies: &[Isometry3<f64>],
        stance: &[bool],
    ) -> Result<Self, FigureError> {
        if bodies.len() != model.bodies.len() {
            return Err(FigureError::BodyCount {
                model: model.name.clone(),
                expected: model.bodies.len(),
                got: bodies.len(),
            });
        }
        if stance.len() != model.feet.len() {
            return Err(FigureError::StanceCount {
                model: model.name.clone(),
                expected: model.feet.len(),
                got: stance.len(),
            });
        }
        let joints: Vec<Point3<f64>> = model
            .joints
            .iter()
            .map(|j| Point3::from((bodies[j.parent] * j.origin).translation.vector))
            .collect();
        // The joint that moves a body: a segment runs from it to every joint (or foot) on the body.
        let driver = |body: usize| model.joints.iter().position(|j| j.child == body);
        let mut bones = Vec::new();
        for (j, joint) in model.joints.iter().enumerate() {
            if let Some(d) = driver(joint.parent) {
                bones.push(Bone {
                    from: joints[d],
                    to: joints[j],
                    part: part_of(joint.leg),
                });
            }
        }
        let feet: Vec<FootMark> = model
            .feet
            .iter()
            .zip(stance)
            .map(|(f, &stance)| FootMark {
                leg: f.leg,
                at: bodies[f.body] * Point3::from(f.point),
                stance,
            })
            .collect();
        for (f, mark) in model.feet.iter().zip(&feet) {
            if let Some(d) = driver(f.body) {
                bones.push(Bone {
                    from: joints[d],
                    to: mark.at,
                    part: part_of(f.leg),
                });
            }
        }
        // Thorax outline: the first joint of each leg on the root body, around the body
        // (left front to hind, then right hind to front).
        let order = [Leg::LF, Leg::LM, Leg::LH, Leg::RH, Leg::RM, Leg::RF];
        let ring: Vec<Point3<f64>> = order
            .iter()
            .filter_map(|leg| {
                model
                    .joints
                    .iter()
                    .position(|j| j.leg == *leg && driver(j.parent).is_none())
                    .map(|j| joints[j])
            })
            .collect();
        for k in 0..ring.len() {
            if ring.len() > 1 {
                bones.push(Bone {
                    from: ring[k],
                    to: ring[(k + 1) % ring.len()],
                    part: Part::Thorax,
                });
            }
        }
        Ok(Self {
            bones,
            joints,
            feet,
        })
    }

    /// The figure of `model` at joint angles `q` (model order), thorax frame.
    pub fn from_angles(model: &Model, q: &[f64], stance: &[bool]) -> Result<Self, FigureError> {
        Self::from_bodies(model, &forward(model, q).bodies, stance)
    }

    /// Every point of the figure (for the drawing's bounds).
    pub fn points(&self) -> impl Iterator<Item = &Point3<f64>> {
        self.joints.iter().chain(self.feet.iter().map(|f| &f.at))
    }
}

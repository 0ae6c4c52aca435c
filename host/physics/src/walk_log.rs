//! What the physics robot records while it walks, one [`WalkSample`] per bus cycle: where the
//! gait was (step, slice, whether it was walking), the thorax pose, the contact force on each foot
//! and, every `pose_every` cycles, every actuated joint's angle (enough to draw the whole body:
//! the thorax pose and the joint angles give every body through forward kinematics), and on the
//! cycles where the simulated gauges were sampled (every `STRAIN_SAMPLE_S`) their readings, so a
//! reading carries the step and slice the firmware played when it was taken.

use planner::model::Leg;

/// One bus cycle of a walk, sampled at the cycle's start. Positions in the world (thorax, foot
/// spheres) are MuJoCo's from the forward pass before its last step, joint angles after it: one
/// timestep (1 ms) apart.
#[derive(Debug, Clone, PartialEq)]
pub struct WalkSample {
    /// Simulated time, s.
    pub time_s: f64,
    /// Steps completed and the table slice the firmware plays (`None`: no gait selected).
    pub playback: Option<(u32, u16)>,
    /// Whether the firmware was playing the gait (not ramping, standing or stopped).
    pub walking: bool,
    /// Thorax position (m) and orientation (quaternion w, x, y, z), world frame.
    pub thorax: ([f64; 3], [f64; 4]),
    /// Contact force on each foot (model feet order), world frame, N.
    pub foot_forces: Vec<(Leg, [f64; 3])>,
    /// Centre of each foot's contact sphere (model feet order), world frame, m.
    pub foot_spheres: Vec<(Leg, [f64; 3])>,
    /// Every model joint's angle (rad; fixed joints 0, forward kinematics ignores them), on
    /// every `pose_every`-th sample.
    pub pose: Option<Vec<f64>>,
    /// Every gauge's simulated reading, microstrain (the model's gauge order), on the cycles
    /// whose start the gauges were sampled at (`crate::STRAIN_SAMPLE_S` apart; None on the
    /// others and for a model without gauges).
    pub strain: Option<Vec<f64>>,
}

/// A walk's samples.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct WalkLog {
    /// A pose is kept every this many samples (at least 1).
    pub pose_every: usize,
    pub samples: Vec<WalkSample>,
}

//! The simulated gauges (`physics::SimulatedGauges`) against the planner's prediction, standing
//! still with the torque bias on (issue 26 item 3).
//!
//! Both go through the same code (`planner::strain::slice_readings`); what differs is the state
//! and the foot forces: the planner's are its QP's (the statically admissible set of least
//! elastic energy), the physics robot's are MuJoCo's after the feet touched down while gravity
//! ramped in. As `standing.rs` explains for the joint torques (3.25 % RMS), some internal force
//! between the feet stays locked in by friction, the contact is a 5 mm sphere's rather than the
//! foot point's, and the joints sit a few mrad off their goals: each moves a gauge's section
//! wrench by a few percent of the weight's share on its leg. Measured at the physics robot's
//! 1 ms (`--no-capture` prints it): 2.46 % RMS of the predicted readings, worst gauge
//! RF_troch_axial off by 15.0 microstrain of a largest predicted 470.6; the bounds are twice that.

use physics::{PhysicsRobot, Plant, SimulatedGauges};
use planner::dynamics::{DynamicsOptions, SliceInput, solve_slice};
use planner::model::builtin;

#[test]
fn standing_with_the_bias_the_simulated_gauges_read_what_the_planner_predicts() {
    let model = builtin("drosophibot2").unwrap();
    let options = PhysicsRobot::options(&model, &planner::terrain::Ground::Flat).unwrap();
    let q = options.stance_q.clone();
    let still = SliceInput::still(&model, q.clone());
    let sol = solve_slice(&model, &still, &DynamicsOptions::default(), 0).unwrap();
    let sites = planner::strain::sites(&model).unwrap();
    let predicted = planner::strain::slice_readings(&model, &sites, &still, &sol.grf);
    let mut plant = Plant::new(&model, &options).unwrap();
    for i in 0..plant.joints().len() {
        let j = plant.joints()[i].clone();
        plant.set_goal(i, q[j.joint] + sol.torque[j.joint] / j.kp, true);
    }
    plant.advance_to(3.0);
    assert!(plant.full_gravity());
    let gauges = SimulatedGauges::new(&model, &plant).unwrap();
    let sim = gauges.read(&plant);
    assert_eq!(sim.names.len(), 36);
    assert_eq!(sim.names[0], "LH_troch_axial");
    let (mut num, mut den, mut worst, mut name) = (0.0, 0.0, 0.0f64, String::new());
    for ((n, s), p) in sim.names.iter().zip(&sim.readings).zip(&predicted) {
        let d = s.microstrain - p.microstrain;
        num += d * d;
        den += p.microstrain * p.microstrain;
        if d.abs() > worst {
            (worst, name) = (d.abs(), n.clone());
        }
    }
    let rel = (num / den).sqrt();
    let peak = predicted
        .iter()
        .map(|p| p.microstrain.abs())
        .fold(0.0, f64::max);
    eprintln!(
        "standing, bias on: simulated vs predicted strain {:.2} % RMS of the prediction, worst \
         {name} {worst:.1} microstrain (largest predicted {peak:.1})",
        rel * 100.0
    );
    assert!(rel < 0.05, "relative RMS {rel}");
    assert!(worst < 30.0, "{name}: {worst} microstrain");
    // Not a trivial agreement: the prediction is hundreds of microstrain somewhere.
    assert!(peak > 100.0, "{peak}");
}

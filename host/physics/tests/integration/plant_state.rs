//! `Plant::state` / `Plant::set_state`, under the vector environment's cheap resets: a fresh
//! plant put into the state another one kept goes on bit for bit as that one did (the reference
//! is the original plant itself, stepped on), and so does the original put back into its own
//! earlier state.

use physics::{PhysicsRobot, Plant};
use planner::model::builtin;
use planner::terrain::Ground;

fn standing_plant() -> Plant {
    let model = builtin("drosophibot2").unwrap();
    let options = PhysicsRobot::options(&model, &Ground::Flat).unwrap();
    let q = options.stance_q.clone();
    let mut plant = Plant::new(&model, &options).unwrap();
    for i in 0..plant.joints().len() {
        let j = plant.joints()[i].clone();
        plant.set_goal(i, q[j.joint], true);
    }
    plant
}

/// Every joint's angle, velocity and torque and the thorax pose, as bits.
fn snapshot(p: &Plant) -> Vec<u64> {
    let mut out: Vec<u64> = (0..p.joints().len())
        .flat_map(|i| {
            let (q, qd, tau) = p.joint_state(i);
            [q.to_bits(), qd.to_bits(), tau.to_bits()]
        })
        .collect();
    let (pos, quat) = p.thorax_pose();
    out.extend(pos.iter().chain(quat.iter()).map(|x| x.to_bits()));
    out.push(p.time().to_bits());
    out
}

#[test]
fn a_plant_put_into_a_kept_state_goes_on_as_the_original() {
    // Mid-way through the gravity ramp (it ends at 1 s): the ramp's clock is part of the state.
    let mut original = standing_plant();
    original.advance_to(0.6);
    let kept = original.state();
    original.advance_to(0.9);
    let reference = snapshot(&original);
    assert_ne!(snapshot(&standing_plant()), reference, "the body moved");

    let mut fresh = standing_plant();
    fresh.set_state(&kept);
    fresh.advance_to(0.9);
    assert_eq!(snapshot(&fresh), reference);

    original.set_state(&kept);
    original.advance_to(0.9);
    assert_eq!(snapshot(&original), reference);
}

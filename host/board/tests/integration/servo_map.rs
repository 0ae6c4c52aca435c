//! Which joint carries which servo is the model file's (drosophibot2.toml, read by
//! `planner::model`: each joint's `servo` ID and its actuator's model). The crates below the
//! planner that cannot read it keep one copy, `dynamixel::sim::DROSOPHIBOT_CTR_IDS` (the IDs of the
//! MX-64s; dynamixel's chains and the firmware's testkit and tests use it); this test holds that
//! copy, the chain built from it and the testkit gait to the model file's map.
//!
//! Independent truth: the paper's layout, MX-64(2.0) on the six CTr joints, MX-28(2.0) on the other
//! sixteen, servo IDs 1 to 22.

use dynamixel::ServoModel;
use dynamixel::sim::{DROSOPHIBOT_CTR_IDS, VirtualChain};
use firmware::testkit::{JOINTS, SyntheticGait};

#[test]
fn the_one_copy_below_the_planner_is_the_model_files_map() {
    let model = planner::model::builtin("drosophibot2").unwrap();
    let mut chain = model.servo_chain();
    chain.sort_by_key(|s| s.0);
    let ids: Vec<u8> = chain.iter().map(|s| s.0).collect();
    assert_eq!(ids, (1..=22).collect::<Vec<u8>>());
    // The paper's layout, joint by joint as the model file names them.
    for j in &model.joints {
        let Some(s) = j.servo else { continue };
        let want = if j.kind == planner::model::JointKind::CTr {
            ServoModel::Mx64
        } else {
            ServoModel::Mx28
        };
        assert_eq!(s.model, want, "{} (servo {})", j.name, s.id);
    }
    // The copy: exactly the model file's MX-64s.
    let mx64: Vec<u8> = chain
        .iter()
        .filter(|s| s.1 == ServoModel::Mx64)
        .map(|s| s.0)
        .collect();
    assert_eq!(mx64, DROSOPHIBOT_CTR_IDS.to_vec());
    // The chain and the testkit gait built from the copy carry the model file's servos.
    let from_copy: Vec<(u8, ServoModel)> = VirtualChain::drosophibot(22, 1_000_000)
        .unwrap()
        .servos()
        .iter()
        .map(|s| (s.id(), s.model()))
        .collect();
    assert_eq!(from_copy, chain);
    let gait: Vec<(u8, ServoModel)> = SyntheticGait::new(2, 1.0)
        .joints
        .iter()
        .map(|j| (j.servo_id, j.model))
        .collect();
    assert_eq!(gait.len(), JOINTS);
    assert_eq!(gait, chain);
}

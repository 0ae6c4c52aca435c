use mujoco_rs::prelude::*;
#[test]
fn smoke() {
    let m = MjModel::from_xml_string("<mujoco><worldbody><body pos='0 0 1'><freejoint/><geom size='.1'/></body><geom type='plane' size='1 1 1'/></worldbody></mujoco>").unwrap();
    let mut d = m.make_data();
    for _ in 0..1000 { d.step(); }
    println!("ncon {}", d.ncon());
}

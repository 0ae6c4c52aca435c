//! Uneven ground (`blocks`): the MJCF export's boxes are the seeded height field as MuJoCo reads
//! them, the same seed gives the same ground, and a robot holding its stance on the blocks rests
//! its feet on the tops under them (contact positions against the known field), its weight on
//! its feet.

use mujoco_rs::prelude::*;
use mujoco_rs::wrappers::mj_model::MjtObjBase;
use physics::{PhysicsRobot, Plant};
use planner::model::{FOOT_RADIUS_M, MjcfOptions, builtin, to_mjcf};
use planner::terrain::{Blocks, Ground};

fn blocks(text: &str) -> Blocks {
    match Ground::parse(text).unwrap() {
        Ground::Blocks(b) => b,
        _ => panic!("{text} is not blocks"),
    }
}

#[test]
fn the_export_holds_the_seeded_heights_and_the_same_seed_the_same_ground() {
    let model = builtin("drosophibot2").unwrap();
    let xml = |t: &str| {
        to_mjcf(
            &model,
            &MjcfOptions::stance(&model, &Ground::parse(t).unwrap()).unwrap(),
        )
    };
    assert_eq!(xml("blocks:7:0.02:0.05:0.1"), xml("blocks:7:0.02:0.05:0.1"));
    assert_ne!(xml("blocks:7:0.02:0.05:0.1"), xml("blocks:8:0.02:0.05:0.1"));
    let b = blocks("blocks:7:0.02:0.05:0.1");
    let mj = MjModel::from_xml_string(&xml("blocks:7:0.02:0.05:0.1")).unwrap();
    let (nx, ny) = b.cells_xy();
    let (mut boxes, mut gaps) = (0, 0);
    for i in 0..nx {
        for j in 0..ny {
            let c = b.cell(i, j);
            let id = mj.name_to_id(MjtObjBase::mjOBJ_GEOM, &format!("block_{i}_{j}"));
            let Some(top) = c.top_m else {
                assert!(id.is_none(), "block_{i}_{j} is a gap");
                gaps += 1;
                continue;
            };
            let g = id.unwrap_or_else(|| panic!("no block_{i}_{j}"));
            // MuJoCo's box: centre and half-sizes; its top is centre + half-height.
            let (pos, size) = (mj.geom_pos()[g], mj.geom_size()[g]);
            assert!((pos[2] + size[2] - top).abs() < 1e-12, "block_{i}_{j}");
            assert!(
                (pos[2] - size[2] - b.floor_m()).abs() < 1e-12,
                "block_{i}_{j} floor"
            );
            assert!((pos[0] - c.centre_xy_m[0]).abs() < 1e-12);
            assert!((size[0] - 0.025).abs() < 1e-12 && (size[1] - 0.025).abs() < 1e-12);
            assert!((0.0..0.02).contains(&top));
            boxes += 1;
        }
    }
    // 3 m x 1.2 m of 50 mm cells; about a tenth of them gaps.
    assert_eq!(boxes + gaps, 60 * 24);
    assert!((100..200).contains(&gaps), "{gaps} gaps");
}

#[test]
fn standing_on_blocks_the_feet_rest_on_the_tops_under_them() {
    let model = builtin("drosophibot2").unwrap();
    let ground = Ground::parse("blocks:7").unwrap();
    let b = blocks("blocks:7");
    let options = PhysicsRobot::options(&model, &ground).unwrap();
    let mut plant = Plant::new(&model, &options).unwrap();
    for i in 0..plant.joints().len() {
        let j = plant.joints()[i].clone();
        plant.set_goal(i, options.stance_q[j.joint], true);
    }
    plant.advance_to(2.5);
    assert!(plant.full_gravity());
    // Standing: the ground carries the weight (within 2 %).
    let normal = plant.contact_normal_total();
    assert!((normal / plant.weight_n() - 1.0).abs() < 0.02, "{normal} N");
    let forces = plant.foot_forces();
    let mut resting = 0;
    for ((leg, c), (_, f)) in plant.foot_positions().into_iter().zip(forces) {
        let tip = c[2] - FOOT_RADIUS_M;
        let under = b.height_at(c[0], c[1]);
        if f[2] > 0.5 {
            // A 5 mm sphere may touch a neighbour's edge when its centre is that close to one.
            if b.edge_distance(c[0], c[1]) > FOOT_RADIUS_M + 1e-3 {
                eprintln!("{}: tip {tip:.5} m on the top at {under:.5} m", leg.name());
                assert!(
                    (tip - under).abs() < 1e-3,
                    "{}: tip {tip} over a top at {under}",
                    leg.name()
                );
                resting += 1;
            }
        } else {
            assert!(
                tip > under - 1e-3,
                "{}: tip {tip} below the top {under}",
                leg.name()
            );
        }
    }
    assert!(resting >= 3, "only {resting} feet rest clear of an edge");
}

//! What the link reports about the gait store after a damaged start-up: a slot that fell back names
//! the copy it lost (seq, CRC, name) in ListGaits and DeviceInfo, and GetJointMap answers the servo
//! IDs of the selected gait.

use core::cell::RefCell;

use protocol::{
    Client, DeviceMessage, FrameAccumulator, JointIds, LossReason, LostCopy, Request, Response,
};

use super::*;
use crate::controller::Config;
use crate::store::nor_double::NorDouble;
use crate::testkit::SyntheticGait;

type Ctl = Controller<NorDouble<4>>;

fn ask(link: &mut Link, c: &RefCell<Ctl>, client: &mut Client, request: Request) -> Response {
    let (seq, frame) = client.request_frame(&request).unwrap();
    let mut out = Vec::new();
    link.receive(c, &frame, &mut |f| out.extend_from_slice(f));
    let mut acc = FrameAccumulator::new();
    let answers: Vec<DeviceMessage> = out
        .iter()
        .filter_map(|&b| acc.push_message::<DeviceMessage>(b))
        .map(|m| m.unwrap())
        .collect();
    match &answers[..] {
        [DeviceMessage::Reply { seq: s, response }] if *s == seq => response.clone(),
        other => panic!("not one reply to {seq}: {other:?}"),
    }
}

/// The synthetic gait of `slices` slices, named `name`.
fn named(slices: usize, name: &str) -> Vec<u8> {
    SyntheticGait::new(slices, 1.0).build_named(name)
}

fn upload(link: &mut Link, c: &RefCell<Ctl>, client: &mut Client, slot: u8, table: &[u8]) {
    let header = protocol::GaitTable::parse(table).unwrap().header();
    let begin = Request::UploadBegin {
        slot,
        header,
        total_len: table.len() as u32,
    };
    assert_eq!(ask(link, c, client, begin), Response::Ack);
    for (i, chunk) in table.chunks(protocol::MAX_CHUNK_LEN).enumerate() {
        let r = Request::UploadChunk {
            offset: (i * protocol::MAX_CHUNK_LEN) as u32,
            data: heapless::Vec::from_slice(chunk).unwrap(),
        };
        assert!(matches!(
            ask(link, c, client, r),
            Response::ChunkAccepted { .. }
        ));
    }
    let commit = Request::UploadCommit {
        crc: protocol::crc32::checksum(table),
    };
    assert!(matches!(
        ask(link, c, client, commit),
        Response::Committed { .. }
    ));
}

#[test]
fn a_slot_that_fell_back_names_the_lost_copy_and_get_joint_map_answers_servo_ids() {
    let c = RefCell::new(Controller::new(NorDouble::new(128), 4, Config::default()));
    let (mut link, mut client) = (Link::new(), Client::new());
    let joint_map = |slot| Request::GetJointMap { slot };
    assert_eq!(
        ask(&mut link, &c, &mut client, joint_map(None)),
        Response::JointMap(None),
        "a fresh board has no gait selected"
    );
    assert_eq!(
        ask(&mut link, &c, &mut client, joint_map(Some(0))),
        Response::JointMap(None),
        "slot 0 is empty"
    );
    assert_eq!(
        ask(&mut link, &c, &mut client, joint_map(Some(4))),
        Response::Error(protocol::ProtocolError::NoSuchSlot { slot: 4, slots: 4 })
    );
    let older = named(40, "tripod-slow");
    let newer = named(50, "tripod-fwd");
    upload(&mut link, &c, &mut client, 0, &older);
    upload(&mut link, &c, &mut client, 0, &newer);
    // The commit selected the new table: its servo IDs are the synthetic chain's, 1..=22.
    let Response::JointMap(Some(JointIds { slot, servo_ids })) =
        ask(&mut link, &c, &mut client, joint_map(None))
    else {
        panic!("no joint map after an upload")
    };
    assert_eq!(slot, 0);
    assert_eq!(servo_ids.as_slice(), (1..=22).collect::<Vec<u8>>());

    // Flip one byte of the newer table's slices in flash (bank B of slot 0, past its 256-byte
    // store header and the table's own header), then start the board again on that flash.
    let flash = c.into_inner().into_flash();
    let mut bytes = flash.window().to_vec();
    let bank = bytes.len() / 8;
    bytes[bank + 256 + 100] ^= 0x10;
    let mut flash = NorDouble::<4>::new(128);
    embedded_storage::nor_flash::NorFlash::write(&mut flash, 0, &bytes).unwrap();
    let c = RefCell::new(Controller::new(flash, 4, Config::default()));
    let (mut link, mut client) = (Link::new(), Client::new());
    let Response::Slots(slots) = ask(&mut link, &c, &mut client, Request::ListGaits) else {
        panic!()
    };
    let s0 = slots[0];
    assert_eq!(s0.gait.unwrap().header.name_str(), Some("tripod-slow"));
    assert_eq!(
        s0.lost,
        Some(LostCopy {
            seq: Some(2),
            crc: Some(protocol::GaitTable::parse(&newer).unwrap().crc()),
            reason: LossReason::TableChecksum,
            name: Some(protocol::GaitTable::parse(&newer).unwrap().header().name),
        })
    );
    assert_eq!(s0.lost.unwrap().name_str(), Some("tripod-fwd"));
    assert!(
        slots[1..]
            .iter()
            .all(|s| s.gait.is_none() && s.lost.is_none())
    );
    let Response::DeviceInfo(info) = ask(&mut link, &c, &mut client, Request::GetDeviceInfo) else {
        panic!()
    };
    assert_eq!(info.slots[0], s0);
    // A board that has selected nothing since start-up names a slot's servos from its table.
    let Response::JointMap(Some(ids)) = ask(&mut link, &c, &mut client, joint_map(Some(0))) else {
        panic!("no joint map of slot 0")
    };
    assert_eq!(ids.servo_ids.as_slice(), (1..=22).collect::<Vec<u8>>());
}

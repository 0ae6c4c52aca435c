//! The host's typed client: sequence numbers, reply matching, errors as data.

use protocol::client::reply;
use protocol::*;

#[test]
fn requests_are_numbered_and_wrap() {
    let mut c = Client::new();
    let mut buf = [0u8; MAX_FRAME_LEN];
    let (seq, frame) = c.encode_request(&Request::GetStatus, &mut buf).unwrap();
    assert_eq!(seq, 0);
    let mut acc = FrameAccumulator::new();
    assert_eq!(
        acc.messages::<HostMessage>(frame).collect::<Vec<_>>(),
        vec![Ok(HostMessage::Request {
            seq: 0,
            request: Request::GetStatus
        })]
    );
    assert_eq!(c.next_seq(), 1);
    let mut c = Client::new();
    for _ in 0..u16::MAX {
        c.request_frame(&Request::Stop).unwrap();
    }
    assert_eq!(c.next_seq(), u16::MAX);
    assert_eq!(c.request_frame(&Request::Stop).unwrap().0, u16::MAX);
    assert_eq!(c.next_seq(), 0);
}

#[test]
fn replies_are_matched_by_seq_and_kind() {
    let status = Status {
        state: RunState::Standing,
        fault: None,
        playback: None,
        upload: None,
        torque_enabled: 0x3F_FFFF,
        counters: Counters::default(),
        health_warning: None,
        health_stop: None,
    };
    let msg = |seq, response| DeviceMessage::Reply { seq, response };
    assert_eq!(
        reply::<Status>(4, msg(4, Response::Status(status.clone()))),
        Ok(status.clone())
    );
    assert_eq!(
        reply::<Status>(4, msg(3, Response::Status(status.clone()))),
        Err(ReplyError::WrongSeq {
            expected: 4,
            got: 3
        })
    );
    assert_eq!(
        reply::<Status>(4, msg(4, Response::Ack)),
        Err(ReplyError::Unexpected)
    );
    assert_eq!(reply::<()>(4, msg(4, Response::Ack)), Ok(()));
    let e = ProtocolError::SlotEmpty { slot: 2 };
    assert_eq!(
        reply::<()>(4, msg(4, Response::Error(e))),
        Err(ReplyError::Device(e))
    );
    assert_eq!(
        reply::<()>(4, DeviceMessage::Rejected(FrameError::Cobs)),
        Err(ReplyError::Rejected(FrameError::Cobs))
    );
    let tel = DeviceMessage::Telemetry(Telemetry {
        time_us: 0,
        cycle: 0,
        step: 0,
        slice: 0,
        joints: heapless::Vec::new(),
        bus: BusStats::default(),
        platform: None,
        state: RunState::Walking,
        health: heapless::Vec::new(),
    });
    assert_eq!(reply::<()>(4, tel), Err(ReplyError::NotAReply));
}

#[test]
fn errors_read_as_sentences_naming_the_place() {
    let e = ProtocolError::Upload(UploadError::OutOfOrder {
        offset: 1024,
        expected: 512,
    });
    assert_eq!(
        e.to_string(),
        "upload: chunk at offset 1024 out of order, expected offset 512"
    );
    let e = ProtocolError::Table(gait::TableError::AngleOutOfLimits {
        slice: 7,
        joint: 3,
        angle: 20000,
    });
    assert_eq!(
        e.to_string(),
        "gait table: slice 7, joint 3: angle 20000 outside the joint limits"
    );
}

#[test]
fn capabilities_combine_as_bits() {
    let caps = Capabilities::GAIT_STORE.union(Capabilities::STREAMING);
    assert_eq!(caps, Capabilities(0b1001));
    assert!(caps.contains(Capabilities::STREAMING));
    assert!(!caps.contains(Capabilities::TELEMETRY));
    assert!(caps.contains(Capabilities::empty()));
}

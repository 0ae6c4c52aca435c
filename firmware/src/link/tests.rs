//! The link dispatcher with real protocol frames: device info, uploads through the protocol's rules
//! into the gait store (every bad chunk sequence refused with its own error, old table intact),
//! garbage, telemetry, and a link that drops mid-frame and comes back.

use core::cell::RefCell;
use std::collections::VecDeque;

use embassy_futures::block_on;
use protocol::{
    Client, DeviceMessage, FrameAccumulator, ProtocolError, Request, Response, UploadError,
};

use super::*;
use crate::controller::Config;
use crate::store::nor_double::NorDouble;
use crate::testkit::SyntheticGait;
use crate::testkit::clock::JumpClock;

type Ctl = Controller<NorDouble<4>>;

fn board() -> RefCell<Ctl> {
    RefCell::new(Controller::new(NorDouble::new(128), 4, Config::default()))
}

/// The controller behind a link, and the host's client talking to it through frames.
struct Host {
    c: RefCell<Ctl>,
    link: Link,
    client: Client,
}

impl Host {
    fn new() -> Self {
        Self {
            c: board(),
            link: Link::new(),
            client: Client::new(),
        }
    }

    /// Sends `request` through a fresh frame and returns the device's one answer, a reply to it.
    fn ask(&mut self, request: Request) -> Response {
        let (seq, frame) = self.client.request_frame(&request).unwrap();
        let answers = self.feed(&frame);
        assert_eq!(answers.len(), 1);
        match &answers[0] {
            DeviceMessage::Reply { seq: s, response } => {
                assert_eq!(*s, seq);
                response.clone()
            }
            other => panic!("not a reply: {other:?}"),
        }
    }

    fn feed(&mut self, bytes: &[u8]) -> Vec<DeviceMessage> {
        let mut out = Vec::new();
        self.link
            .receive(&self.c, bytes, &mut |f| out.extend_from_slice(f));
        decode_all(&out)
    }

    fn status(&mut self) -> protocol::Status {
        match self.ask(Request::GetStatus) {
            Response::Status(s) => s,
            other => panic!("GetStatus answered {other:?}"),
        }
    }

    /// Uploads `table` into `slot` (begin and every chunk must be accepted); the commit's answer.
    fn upload(&mut self, slot: u8, table: &[u8]) -> Response {
        let header = protocol::GaitTable::parse(table).unwrap().header();
        let r = self.ask(Request::UploadBegin {
            slot,
            header,
            total_len: table.len() as u32,
        });
        assert_eq!(r, Response::Ack);
        for (i, chunk) in table.chunks(protocol::MAX_CHUNK_LEN).enumerate() {
            let r = self.ask(Request::UploadChunk {
                offset: (i * protocol::MAX_CHUNK_LEN) as u32,
                data: heapless::Vec::from_slice(chunk).unwrap(),
            });
            assert!(matches!(r, Response::ChunkAccepted { .. }), "{r:?}");
        }
        self.ask(Request::UploadCommit {
            crc: protocol::crc32::checksum(table),
        })
    }
}

fn decode_all(bytes: &[u8]) -> Vec<DeviceMessage> {
    let mut acc = FrameAccumulator::new();
    acc.messages::<DeviceMessage>(bytes)
        .map(|m| m.expect("the board sends valid frames"))
        .collect()
}

#[test]
fn device_info_upload_and_list() {
    let mut h = Host::new();
    let Response::DeviceInfo(info) = h.ask(Request::GetDeviceInfo) else {
        panic!()
    };
    assert_eq!(info.protocol_version, protocol::PROTOCOL_VERSION);
    assert_eq!(info.slots.len(), 4);
    assert!(info.slots.iter().all(|s| s.gait.is_none()));
    let table = SyntheticGait::new(50, 1.0).build();
    let crc = protocol::crc32::checksum(&table);
    assert_eq!(h.upload(2, &table), Response::Committed { slot: 2, crc });
    let Response::Slots(slots) = h.ask(Request::ListGaits) else {
        panic!()
    };
    assert_eq!(slots[2].gait.unwrap().header.slice_count, 50);
    assert!(slots[0].gait.is_none());
    assert_eq!(h.c.borrow().store().table(2), Some(&table[..]));
}

#[test]
fn every_bad_upload_is_refused_with_its_own_error_and_the_old_table_stays() {
    let mut h = Host::new();
    let old = SyntheticGait::new(40, 1.0).build();
    h.upload(1, &old);
    let new = SyntheticGait::new(60, 2.0).build();
    let header = protocol::GaitTable::parse(&new).unwrap().header();
    let total_len = new.len() as u32;
    let chunk = |offset: usize, len: usize| Request::UploadChunk {
        offset: offset as u32,
        data: heapless::Vec::from_slice(&new[offset..offset + len]).unwrap(),
    };
    let begin = Request::UploadBegin {
        slot: 1,
        header,
        total_len,
    };
    let err = |r: Response| match r {
        Response::Error(ProtocolError::Upload(e)) => e,
        other => panic!("expected an upload error, got {other:?}"),
    };
    let check_old = |c: &RefCell<Ctl>| {
        assert_eq!(c.borrow().store().table(1), Some(&old[..]));
    };

    // Reordered: the second chunk first.
    assert_eq!(h.ask(begin.clone()), Response::Ack);
    assert_eq!(
        err(h.ask(chunk(512, 512))),
        UploadError::OutOfOrder {
            offset: 512,
            expected: 0
        }
    );
    // Duplicated: the first chunk twice.
    h.ask(chunk(0, 512));
    assert_eq!(
        err(h.ask(chunk(0, 512))),
        UploadError::Duplicate {
            offset: 0,
            received: 512
        }
    );
    // Oversized: a chunk longer than MAX_CHUNK_LEN cannot even be encoded (heapless::Vec); a chunk
    // reaching past the announced end:
    let mut past = 512;
    while past + 512 < new.len() {
        h.ask(chunk(past, 512));
        past += 512;
    }
    let r = h.ask(Request::UploadChunk {
        offset: past as u32,
        data: heapless::Vec::from_slice(&[0u8; 512]).unwrap(),
    });
    assert_eq!(
        err(r),
        UploadError::PastEnd {
            offset: past as u32,
            len: 512,
            total_len
        }
    );
    // Truncated: commit before the last chunk.
    assert_eq!(
        err(h.ask(Request::UploadCommit {
            crc: protocol::crc32::checksum(&new)
        })),
        UploadError::Truncated {
            received: past as u32,
            total_len
        }
    );
    check_old(&h.c);
    // Wrong checksum: all bytes, a CRC that is not theirs.
    h.ask(chunk(past, new.len() - past));
    let good = protocol::crc32::checksum(&new);
    assert_eq!(
        err(h.ask(Request::UploadCommit { crc: good ^ 0x10 })),
        UploadError::ChecksumMismatch {
            expected: good ^ 0x10,
            computed: good
        }
    );
    check_old(&h.c);
    // Too large for a slot.
    let mut big = header;
    big.slice_count = 10_000;
    let r = h.ask(Request::UploadBegin {
        slot: 1,
        header: big,
        total_len: big.table_len(),
    });
    assert!(matches!(err(r), UploadError::TooLarge { .. }));
    check_old(&h.c);
    // And a good upload still goes through afterwards.
    assert_eq!(
        h.upload(1, &new),
        Response::Committed { slot: 1, crc: good }
    );
    assert_eq!(h.c.borrow().store().table(1), Some(&new[..]));
}

#[test]
fn garbage_is_rejected_and_the_next_request_answered() {
    let mut h = Host::new();
    let answers = h.feed(&[1, 2, 3, 0xFF, 7, 0]);
    assert!(matches!(answers[..], [DeviceMessage::Rejected(_)]));
    assert_eq!(h.link.rejected, 1);
    let s = h.status();
    assert_eq!(s.counters.rejected_frames, 1);
}

#[test]
fn commands_reach_the_controller_and_errors_come_back_as_data() {
    let mut h = Host::new();
    // One bus cycle: no servos known, so Boot is over at once.
    {
        let mut ctl = h.c.borrow_mut();
        let plan = ctl.plan(0);
        ctl.complete(&plan, crate::controller::Outcome::Done(Ok(())), &[], 0);
    }
    // No gait: playing slot 0 is refused with the slot named.
    let play = Request::Play(protocol::PlayCommand {
        slot: 0,
        direction: protocol::Direction::Forward,
        period_scale: 1000,
        steps: protocol::Steps::Count(1),
    });
    assert_eq!(
        h.ask(play),
        Response::Error(ProtocolError::SlotEmpty { slot: 0 })
    );
    assert_eq!(h.ask(Request::EmergencyStop), Response::Ack);
    let s = h.status();
    assert_eq!(s.state, protocol::RunState::Fault);
    assert_eq!(s.fault.unwrap().kind, protocol::FaultKind::EmergencyStop);
    assert_eq!(h.ask(Request::ClearFault), Response::Ack);
    assert_eq!(
        h.ask(Request::SetBus {
            baud: 1_000_000,
            cycle_hz: 20
        }),
        Response::Error(ProtocolError::InvalidSetting {
            setting: protocol::Setting::CycleRate,
            value: 20
        })
    );
}

/// Host side of an in-memory link: chunks to deliver, then either silence or a drop.
struct Pipe {
    input: VecDeque<Vec<u8>>,
    output: Vec<u8>,
    drop_when_empty: bool,
    reads_left: usize,
}

impl embedded_io_async::ErrorType for Pipe {
    type Error = LinkDown;
}
impl embedded_io_async::Read for Pipe {
    async fn read(&mut self, buf: &mut [u8]) -> Result<usize, LinkDown> {
        match self.input.pop_front() {
            Some(chunk) => {
                buf[..chunk.len()].copy_from_slice(&chunk);
                Ok(chunk.len())
            }
            None if self.drop_when_empty || self.reads_left == 0 => Err(LinkDown),
            None => {
                self.reads_left -= 1;
                core::future::pending().await
            }
        }
    }
}
impl embedded_io_async::Write for Pipe {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, LinkDown> {
        self.output.extend_from_slice(buf);
        Ok(buf.len())
    }
    async fn flush(&mut self) -> Result<(), LinkDown> {
        Ok(())
    }
}

#[test]
fn a_link_that_drops_mid_frame_comes_back_and_telemetry_flows() {
    let mut h = Host::new();
    h.c.borrow_mut().set_telemetry(1);
    let clock = JumpClock::default();
    let (_, frame) = h.client.request_frame(&Request::GetStatus).unwrap();
    // First connection: half a frame, then the cable is pulled.
    let mut pipe = Pipe {
        input: VecDeque::from([frame[..frame.len() / 2].to_vec()]),
        output: vec![],
        drop_when_empty: true,
        reads_left: 0,
    };
    assert_eq!(
        block_on(serve(&mut h.link, &h.c, &mut pipe, &clock)),
        LinkEnd::Dropped
    );
    assert!(pipe.output.is_empty());
    // The robot carries on meanwhile: a few bus cycles queue telemetry.
    for t in 0..3 {
        let mut ctl = h.c.borrow_mut();
        let plan = ctl.plan(t * 10_000);
        ctl.complete(&plan, crate::controller::Outcome::Done(Ok(())), &[], 0);
    }
    // Second connection: a whole frame is answered (the stale half was forgotten), telemetry follows.
    let (seq, frame) = h.client.request_frame(&Request::GetStatus).unwrap();
    let mut pipe = Pipe {
        input: VecDeque::from([frame]),
        output: vec![],
        drop_when_empty: false,
        reads_left: 2,
    };
    assert_eq!(
        block_on(serve(&mut h.link, &h.c, &mut pipe, &clock)),
        LinkEnd::Dropped
    );
    let got = decode_all(&pipe.output);
    assert!(
        matches!(&got[0], DeviceMessage::Reply { seq: s, response: Response::Status(_) } if *s == seq)
    );
    let telemetry: Vec<u32> = got[1..]
        .iter()
        .map(|m| match m {
            DeviceMessage::Telemetry(t) => t.cycle,
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(telemetry, [1, 2, 3]);
}

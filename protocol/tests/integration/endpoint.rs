//! Typed requests end to end in memory: the host names a request by its struct and gets the reply
//! type back; a board implements `Handler` and answers through `dispatch`. No hardware, no I/O.

use protocol::client::reply;
use protocol::endpoint::{self as ep, Endpoint, Handler, Slots, dispatch};
use protocol::*;

/// A board double: a bus setting it keeps, a status it reports, everything else unsupported.
struct FakeBoard {
    baud: u32,
    cycle_hz: u16,
    /// Servo IDs of the selected gait, if one is selected.
    joint_ids: Option<JointIds>,
}

fn unsupported<T>() -> Result<T, ProtocolError> {
    Err(ProtocolError::Unsupported)
}

impl Handler for FakeBoard {
    fn queue_gait(&mut self, _: QueueCommand) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn clear_queue(&mut self, _: ep::ClearQueue) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn set_steer_family(&mut self, _: SteerFamily) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn steer(&mut self, _: SteerCommand) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn set_platform(&mut self, _: PlatformSetup) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn set_health_limits(&mut self, _: HealthLimits) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn read_servo(&mut self, _: ServoRead) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn get_servo_read(
        &mut self,
        _: ep::GetServoRead,
    ) -> Result<Option<ServoReadResult>, ProtocolError> {
        unsupported()
    }
    fn clear_platform(&mut self, _: ep::ClearPlatform) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn get_platform(
        &mut self,
        _: ep::GetPlatform,
    ) -> Result<Option<PlatformStatus>, ProtocolError> {
        unsupported()
    }
    fn get_device_info(&mut self, _: ep::GetDeviceInfo) -> Result<DeviceInfo, ProtocolError> {
        unsupported()
    }
    fn get_status(&mut self, _: ep::GetStatus) -> Result<Status, ProtocolError> {
        Ok(Status {
            state: RunState::Standing,
            fault: None,
            playback: None,
            upload: None,
            torque_enabled: 0b11,
            counters: Counters::default(),
            health_warning: None,
            health_stop: None,
        })
    }
    fn list_gaits(&mut self, _: ep::ListGaits) -> Result<Slots, ProtocolError> {
        unsupported()
    }
    fn upload_begin(&mut self, _: ep::UploadBegin) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn upload_chunk(&mut self, r: ep::UploadChunk) -> Result<ep::ChunkAccepted, ProtocolError> {
        Ok(ep::ChunkAccepted {
            received: r.offset + r.data.len() as u32,
        })
    }
    fn upload_commit(&mut self, _: ep::UploadCommit) -> Result<ep::Committed, ProtocolError> {
        unsupported()
    }
    fn upload_abort(&mut self, _: ep::UploadAbort) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn delete_gait(&mut self, _: ep::DeleteGait) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn play(&mut self, _: PlayCommand) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn stop(&mut self, _: ep::Stop) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn set_period_scale(&mut self, _: ep::SetPeriodScale) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn get_settings(&mut self, _: ep::GetSettings) -> Result<Settings, ProtocolError> {
        unsupported()
    }
    fn set_bus(&mut self, r: ep::SetBus) -> Result<(), ProtocolError> {
        if r.cycle_hz == 0 {
            return Err(ProtocolError::InvalidSetting {
                setting: Setting::CycleRate,
                value: 0,
            });
        }
        (self.baud, self.cycle_hz) = (r.baud, r.cycle_hz);
        Ok(())
    }
    fn set_stiffness(&mut self, _: ep::SetStiffness) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn set_limits(&mut self, _: ep::SetLimits) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn set_torque(&mut self, _: ep::SetTorque) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn reboot_servos(&mut self, _: ep::RebootServos) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn emergency_stop(&mut self, _: ep::EmergencyStop) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn clear_fault(&mut self, _: ep::ClearFault) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn set_telemetry(&mut self, _: ep::SetTelemetry) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn enter_streaming(&mut self, _: StreamConfig) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn leave_streaming(&mut self, _: ep::LeaveStreaming) -> Result<(), ProtocolError> {
        unsupported()
    }
    fn get_joint_map(&mut self, r: ep::GetJointMap) -> Result<Option<JointIds>, ProtocolError> {
        let ids = self.joint_ids.clone();
        Ok(match r.slot {
            None => ids,
            Some(slot) => ids.filter(|j| j.slot == slot),
        })
    }
}

/// One typed call over framed bytes: host encodes, board decodes and dispatches, host decodes the
/// reply as the endpoint's reply type.
fn call<E: Endpoint>(
    board: &mut FakeBoard,
    client: &mut Client,
    request: E,
) -> Result<E::Reply, ReplyError> {
    let (seq, frame) = client.request_frame(&request.into()).unwrap();
    let mut acc = FrameAccumulator::new();
    let Some(Ok(HostMessage::Request { seq: got, request })) =
        acc.messages::<HostMessage>(&frame).next()
    else {
        panic!("the board could not decode the request frame");
    };
    let mut out = [0u8; MAX_FRAME_LEN];
    let back = encode_frame(
        &DeviceMessage::Reply {
            seq: got,
            response: dispatch(board, request),
        },
        &mut out,
    )
    .unwrap();
    let mut acc = FrameAccumulator::new();
    let message = acc.messages::<DeviceMessage>(back).next().unwrap().unwrap();
    reply::<E::Reply>(seq, message)
}

#[test]
fn typed_calls_round_trip_with_their_reply_types() {
    let mut board = FakeBoard {
        baud: 57_600,
        cycle_hz: 50,
        joint_ids: None,
    };
    let mut client = Client::new();
    let status: Status = call(&mut board, &mut client, ep::GetStatus).unwrap();
    assert_eq!(
        (status.state, status.torque_enabled),
        (RunState::Standing, 0b11)
    );
    let ack: () = call(
        &mut board,
        &mut client,
        ep::SetBus {
            baud: 1_000_000,
            cycle_hz: 100,
        },
    )
    .unwrap();
    assert_eq!(ack, ());
    assert_eq!((board.baud, board.cycle_hz), (1_000_000, 100));
    let data = heapless::Vec::from_slice(&[1, 2, 3]).unwrap();
    let accepted = call(
        &mut board,
        &mut client,
        ep::UploadChunk { offset: 10, data },
    )
    .unwrap();
    assert_eq!(accepted, ep::ChunkAccepted { received: 13 });
}

#[test]
fn get_joint_map_answers_the_selected_gaits_servo_ids_or_none() {
    let mut board = FakeBoard {
        baud: 57_600,
        cycle_hz: 50,
        joint_ids: None,
    };
    let mut client = Client::new();
    let none: Option<JointIds> =
        call(&mut board, &mut client, ep::GetJointMap { slot: None }).unwrap();
    assert_eq!(none, None, "no gait selected");
    let ids = JointIds {
        slot: 2,
        servo_ids: heapless::Vec::from_slice(&[11, 12, 13, 21]).unwrap(),
    };
    board.joint_ids = Some(ids.clone());
    let got = call(&mut board, &mut client, ep::GetJointMap { slot: None }).unwrap();
    assert_eq!(got, Some(ids.clone()));
    let got = call(&mut board, &mut client, ep::GetJointMap { slot: Some(2) }).unwrap();
    assert_eq!(got, Some(ids));
    let got = call(&mut board, &mut client, ep::GetJointMap { slot: Some(1) }).unwrap();
    assert_eq!(got, None, "slot 1 holds nothing");
    // GetJointMap is appended after LeaveStreaming (21): variant 22 of Request, then the Option.
    assert_eq!(
        postcard::to_allocvec(&Request::from(ep::GetJointMap { slot: Some(3) })).unwrap(),
        [22, 1, 3]
    );
}

#[test]
fn handler_errors_travel_back_as_data() {
    let mut board = FakeBoard {
        baud: 57_600,
        cycle_hz: 50,
        joint_ids: None,
    };
    let mut client = Client::new();
    let refused = call(
        &mut board,
        &mut client,
        ep::SetBus {
            baud: 1_000_000,
            cycle_hz: 0,
        },
    );
    assert_eq!(
        refused,
        Err(ReplyError::Device(ProtocolError::InvalidSetting {
            setting: Setting::CycleRate,
            value: 0
        }))
    );
    assert_eq!(
        (board.baud, board.cycle_hz),
        (57_600, 50),
        "nothing changed"
    );
    assert_eq!(
        call(&mut board, &mut client, ep::Stop),
        Err(ReplyError::Device(ProtocolError::Unsupported))
    );
}

#[test]
fn an_endpoint_encodes_exactly_as_its_request_variant() {
    // SetBus is variant 12 of Request; 1_000_000 as a varint is C0 84 3D, 100 is 64.
    let bytes = postcard::to_allocvec(&Request::from(ep::SetBus {
        baud: 1_000_000,
        cycle_hz: 100,
    }))
    .unwrap();
    assert_eq!(bytes, [12, 0xC0, 0x84, 0x3D, 0x64]);
    // A wrapping variant carries its struct: Play is variant 8.
    let play = Request::from(PlayCommand {
        slot: 1,
        direction: Direction::Backward,
        period_scale: 1000,
        steps: Steps::Count(3),
    });
    assert_eq!(
        postcard::to_allocvec(&play).unwrap(),
        [8, 1, 1, 0xE8, 0x07, 1, 3]
    );
}

#[test]
fn names_of_requests_are_their_endpoint_names() {
    assert_eq!(Request::from(ep::GetStatus).name(), "GetStatus");
    assert_eq!(ep::GetStatus::NAME, "GetStatus");
    assert_eq!(<PlayCommand as Endpoint>::NAME, "Play");
    assert_eq!(
        Request::from(StreamConfig {
            timeout_cycles: 3,
            feedback_every: 1
        })
        .name(),
        "EnterStreaming"
    );
    assert_eq!(ep::LeaveStreaming::NAME, Request::LeaveStreaming.name());
}

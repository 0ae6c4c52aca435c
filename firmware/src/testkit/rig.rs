//! The whole board on the simulated wire: link, controller, bus loop and bus master over the NOR
//! flash double and the dynamixel crate's half-duplex wire with 22 virtual servos, on simulated
//! time; and the host's side of the link (requests, uploads, play), answered in process.

use std::vec;
use std::vec::Vec;

use dynamixel::master::AutoDirection;
use dynamixel::sim::SimWire;
use embedded_io_async::{Read, ReadReady, Write};
use protocol::{
    Client, DeviceMessage, FrameAccumulator, PlayCommand, Request, Response, Status, Steps,
    Telemetry,
};

use super::JOINTS;
use crate::board::Board;
use crate::controller::Config;
use crate::safety::State;
use crate::store::nor_double::NorDouble;

/// A board whose bus is reached through `IO` (the wire itself, or a tap on it), clocked by the wire.
pub type SimBoardOn<IO> = Board<NorDouble<4>, IO, AutoDirection, SimWire>;
/// A board straight on the simulated wire.
pub type SimBoard = SimBoardOn<SimWire>;

/// Flash sectors of the double: 4 slots of two banks, each bank large enough for the synthetic gait.
pub const SECTORS: usize = 128;

/// Slack the bus master allows after a reply's expected end, us: replies come back to back at
/// Return Delay Time 0, and 100 us covers the parser's chunking.
const REPLY_SLACK_US: u32 = 100;

/// 22 virtual servos (the robot's chain) on a simulated wire with echo at `baud`, Return Delay
/// Time 0.
pub fn wire(baud: u32) -> SimWire {
    SimWire::drosophibot(JOINTS as u8, baud, 0).expect("the robot's chain")
}

/// A board on `flash` with `config`, its bus reached through `io` and clocked by `wire`.
pub fn board_on<IO>(flash: NorDouble<4>, config: Config, io: IO, wire: &SimWire) -> SimBoardOn<IO>
where
    IO: Read + ReadReady + Write,
{
    Board::new(
        flash,
        4,
        config,
        io,
        AutoDirection,
        wire.clone(),
        REPLY_SLACK_US,
    )
}

/// A board with an empty store, wired to the 22 servos at `baud`, cycling at `cycle_hz`.
pub fn rig(baud: u32, cycle_hz: u16) -> (SimBoard, SimWire) {
    let wire = wire(baud);
    let config = Config {
        cycle_hz,
        baud,
        ..Config::default()
    };
    let board = board_on(NorDouble::new(SECTORS), config, wire.clone(), &wire);
    (board, wire)
}

/// Every message the board sends for `bytes` from the host.
pub fn exchange<IO: Read + ReadReady + Write>(
    board: &mut SimBoardOn<IO>,
    bytes: &[u8],
) -> Vec<DeviceMessage> {
    let mut out = Vec::new();
    board.receive(bytes, |f| out.extend_from_slice(f));
    let mut acc = FrameAccumulator::new();
    acc.messages::<DeviceMessage>(&out)
        .map(|m| m.expect("the board sends valid frames"))
        .collect()
}

/// Sends one request through the link and returns its reply (checked to carry the request's seq).
pub fn ask<IO: Read + ReadReady + Write>(
    board: &mut SimBoardOn<IO>,
    client: &mut Client,
    request: Request,
) -> Response {
    let (seq, frame) = client.request_frame(&request).expect("the request encodes");
    for m in exchange(board, &frame) {
        if let DeviceMessage::Reply { seq: s, response } = m {
            assert_eq!(s, seq);
            return response;
        }
    }
    panic!("no reply to {request:?}");
}

/// The board's status.
pub fn status<IO: Read + ReadReady + Write>(
    board: &mut SimBoardOn<IO>,
    client: &mut Client,
) -> Status {
    match ask(board, client, Request::GetStatus) {
        Response::Status(s) => s,
        other => panic!("GetStatus answered {other:?}"),
    }
}

/// The CRC of each slot's gait (None: empty).
pub fn slots<IO: Read + ReadReady + Write>(
    board: &mut SimBoardOn<IO>,
    client: &mut Client,
) -> Vec<Option<u32>> {
    match ask(board, client, Request::ListGaits) {
        Response::Slots(s) => s.iter().map(|i| i.gait.map(|g| g.crc)).collect(),
        other => panic!("ListGaits answered {other:?}"),
    }
}

/// The upload requests for `table` into `slot`, begin to commit, in protocol-sized chunks.
pub fn upload_requests(slot: u8, table: &[u8]) -> Vec<Request> {
    let header = protocol::GaitTable::parse(table)
        .expect("a valid table")
        .header();
    let mut r = vec![Request::UploadBegin {
        slot,
        header,
        total_len: table.len() as u32,
    }];
    for (i, c) in table.chunks(protocol::MAX_CHUNK_LEN).enumerate() {
        r.push(Request::UploadChunk {
            offset: (i * protocol::MAX_CHUNK_LEN) as u32,
            data: heapless::Vec::from_slice(c).expect("a chunk fits"),
        });
    }
    r.push(Request::UploadCommit {
        crc: protocol::crc32::checksum(table),
    });
    r
}

/// Uploads `table` into `slot`; every step must be accepted and the commit name slot and CRC.
pub fn upload<IO: Read + ReadReady + Write>(
    board: &mut SimBoardOn<IO>,
    client: &mut Client,
    slot: u8,
    table: &[u8],
) {
    let crc = protocol::crc32::checksum(table);
    for req in upload_requests(slot, table) {
        let r = ask(board, client, req);
        assert!(
            matches!(r, Response::Ack | Response::ChunkAccepted { .. })
                || r == (Response::Committed { slot, crc }),
            "{r:?}"
        );
    }
}

/// Plays slot 0 forward at its own period for `steps`; the board must accept.
pub fn play<IO: Read + ReadReady + Write>(
    board: &mut SimBoardOn<IO>,
    client: &mut Client,
    steps: Steps,
) {
    let r = ask(
        board,
        client,
        Request::Play(PlayCommand {
            slot: 0,
            direction: protocol::Direction::Forward,
            period_scale: 1000,
            steps,
        }),
    );
    assert_eq!(r, Response::Ack);
}

/// One bus cycle; the telemetry it produced.
pub fn cycle<IO: Read + ReadReady + Write>(
    board: &mut SimBoardOn<IO>,
    wire: &SimWire,
) -> Vec<Telemetry> {
    wire.block_on(board.run_cycle());
    telemetry(board)
}

/// The telemetry records the board has queued, taken off it.
pub fn telemetry<IO: Read + ReadReady + Write>(board: &mut SimBoardOn<IO>) -> Vec<Telemetry> {
    let mut out = Vec::new();
    board.drain_telemetry(|f| out.extend_from_slice(f));
    let mut acc = FrameAccumulator::new();
    acc.messages::<DeviceMessage>(&out)
        .filter_map(|m| match m {
            Ok(DeviceMessage::Telemetry(t)) => Some(t),
            _ => None,
        })
        .collect()
}

/// A board at `baud` and `cycle_hz` with `table` in slot 0, just told to play it for `steps`:
/// booted, the table uploaded, the servos found, and the play accepted.
pub fn playing(
    baud: u32,
    cycle_hz: u16,
    table: &[u8],
    steps: Steps,
) -> (SimBoard, SimWire, Client) {
    let (mut board, wire) = rig(baud, cycle_hz);
    let mut client = Client::new();
    run_until(&mut board, &wire, 5, |s| s == State::Idle);
    upload(&mut board, &mut client, 0, table);
    run_until(&mut board, &wire, 5, |s| s == State::Idle);
    play(&mut board, &mut client, steps);
    (board, wire, client)
}

/// A board at `baud` and `cycle_hz` walking continuously with `table` in slot 0: booted, the
/// table uploaded, the servos found, played, and past its start ramp.
pub fn walking(baud: u32, cycle_hz: u16, table: &[u8]) -> (SimBoard, SimWire, Client) {
    let (mut board, wire, client) = playing(baud, cycle_hz, table, Steps::Continuous);
    run_until(&mut board, &wire, 5000, |s| s == State::Walking);
    (board, wire, client)
}

/// Each joint's servo position on the wire and the goal the board sent it, one entry a recorded
/// cycle: `present[j][k]` and `goal[j][k]`.
#[derive(Debug, Clone)]
pub struct JointTrace {
    pub present: Vec<Vec<i32>>,
    pub goal: Vec<Vec<i32>>,
}

impl Default for JointTrace {
    fn default() -> Self {
        Self {
            present: vec![vec![]; JOINTS],
            goal: vec![vec![]; JOINTS],
        }
    }
}

impl JointTrace {
    /// Appends every servo's present position and the board's last goal for it.
    pub fn record<IO>(&mut self, board: &SimBoardOn<IO>, wire: &SimWire) {
        let goals = board.controller.borrow().goals().to_vec();
        wire.with_chain(|c| {
            for (j, s) in c.servos().iter().enumerate() {
                self.present[j].push(s.position_ticks());
                self.goal[j].push(goals[j]);
            }
        });
    }
}

/// The controller's safety state.
pub fn state<IO>(board: &SimBoardOn<IO>) -> State {
    board.controller.borrow().state()
}

/// Runs bus cycles (telemetry discarded) until `done` holds for the state; panics after `max`.
/// Returns the cycles run.
pub fn run_until<IO: Read + ReadReady + Write>(
    board: &mut SimBoardOn<IO>,
    wire: &SimWire,
    max: usize,
    done: impl Fn(State) -> bool,
) -> usize {
    for i in 0..max {
        if done(state(board)) {
            return i;
        }
        cycle(board, wire);
    }
    panic!("not done after {max} cycles: {:?}", state(board));
}

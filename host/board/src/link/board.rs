//! [`Board`]: the typed client. Numbers requests, waits for the matching reply on the transport's
//! clock, sets telemetry aside for [`Board::telemetry`], and turns every failure into a
//! [`LinkError`] that names the port and the request.

use std::collections::VecDeque;
use std::time::Duration;

use protocol::client::Reply;
use protocol::endpoint::{self as ep, Endpoint};
use protocol::{
    Client, DeviceInfo, DeviceMessage, FrameAccumulator, Proprioception, ProtocolError, Request,
    Response, RunState, ServoSelect, Settings, SlotInfo, Status, Telemetry,
};

use super::error::LinkError;
use super::transport::{Transport, TransportError};
use super::version::{ForeignInfo, device_info_prefix};
use crate::rules::period::{CheckedPlay, CheckedQueue};
use crate::rules::steer::CheckedSteer;
use crate::rules::stiffness::Stiffness;

/// How long a request waits for its reply by default. Flash work on the board (a sector erase
/// per chunk) stays well below it.
pub const DEFAULT_REPLY_TIMEOUT: Duration = Duration::from_secs(2);

/// How long a request waits for a board that is still booting (looking for its servos).
pub const BOOT_WAIT: Duration = Duration::from_secs(1);

/// Telemetry records kept while nobody reads them; older ones are dropped (and counted).
const TELEMETRY_BACKLOG: usize = 100_000;

/// Most bytes taken from the transport at a time.
const RX_CHUNK: usize = 4096;

/// A connected board whose protocol and table format versions match this host's.
#[derive(Debug)]
pub struct Board<T: Transport> {
    transport: T,
    client: Client,
    acc: FrameAccumulator,
    /// Receive buffer of [`Board::next_message`], kept so that each call does not zero 4 KB anew.
    rx: Box<[u8; RX_CHUNK]>,
    inbox: VecDeque<DeviceMessage>,
    telemetry: VecDeque<Telemetry>,
    /// Streaming feedback set aside for [`Board::proprioception`] (see `stream.rs`).
    pub(super) proprioception: VecDeque<Proprioception>,
    info: DeviceInfo,
    reply_timeout: Duration,
    /// Frames from the board that failed to decode.
    bad_frames: u64,
    /// Telemetry records dropped from the backlog.
    telemetry_dropped: u64,
    /// A `DeviceInfo` reply of another protocol version that did not decode as a whole.
    foreign: Option<ForeignInfo>,
    /// The steering family this host last set and the board accepted (for the servo check of a
    /// steered walk faster than planned, `rules::steer`).
    steer_family: Option<protocol::SteerFamily>,
}

impl<T: Transport> Board<T> {
    /// Asks the board who it is and refuses a board of another protocol or table format version
    /// (having sent it nothing but that question).
    pub fn connect(transport: T) -> Result<Self, LinkError> {
        Self::connect_within(transport, DEFAULT_REPLY_TIMEOUT)
    }

    /// [`Board::connect`] waiting `reply_timeout` for each reply (from the first one on).
    pub fn connect_within(transport: T, reply_timeout: Duration) -> Result<Self, LinkError> {
        let mut board = Self {
            transport,
            client: Client::new(),
            acc: FrameAccumulator::new(),
            rx: Box::new([0; RX_CHUNK]),
            inbox: VecDeque::new(),
            telemetry: VecDeque::new(),
            proprioception: VecDeque::new(),
            info: placeholder_info(),
            reply_timeout,
            bad_frames: 0,
            telemetry_dropped: 0,
            foreign: None,
            steer_family: None,
        };
        // A lone delimiter ends whatever partial frame an earlier session left in the board's
        // receiver, so our first request is not glued to garbage.
        board.send_raw(&[0])?;
        let info = board.call(ep::GetDeviceInfo)?;
        let port = board.port().to_owned();
        if info.protocol_version != protocol::PROTOCOL_VERSION {
            return Err(LinkError::ProtocolVersion {
                port,
                board: info.protocol_version,
                host: protocol::PROTOCOL_VERSION,
            });
        }
        if info.table_format_version != protocol::gait::FORMAT_VERSION {
            return Err(LinkError::TableFormat {
                port,
                board: info.table_format_version,
                host: protocol::gait::FORMAT_VERSION,
            });
        }
        board.info = info;
        board.wait_booted()?;
        Ok(board)
    }

    /// Waits (up to [`BOOT_WAIT`] on the transport's clock) while the board reports Boot, so a
    /// board that has just been powered or reset (the virtual robot, at every command) is reported
    /// and driven in the state it boots into. A board still booting after that is left as it is:
    /// its status says Boot.
    pub fn wait_booted(&mut self) -> Result<(), LinkError> {
        let give_up = self.transport.now() + BOOT_WAIT;
        while self.status()?.state == RunState::Boot && self.transport.now() < give_up {
            self.wait(Duration::from_millis(20))?;
        }
        Ok(())
    }

    /// The board's answer to `GetDeviceInfo` at connection.
    pub fn info(&self) -> &DeviceInfo {
        &self.info
    }

    /// The port's name.
    pub fn port(&self) -> &str {
        self.transport.name()
    }

    /// The transport (e.g. to reach the virtual robot behind it).
    pub fn transport(&self) -> &T {
        &self.transport
    }

    pub fn transport_mut(&mut self) -> &mut T {
        &mut self.transport
    }

    /// Gives the transport back.
    pub fn into_transport(self) -> T {
        self.transport
    }

    /// The transport's clock (simulated time on the virtual robot).
    pub fn now(&self) -> Duration {
        self.transport.now()
    }

    /// Changes how long requests wait for their reply.
    pub fn set_reply_timeout(&mut self, timeout: Duration) {
        self.reply_timeout = timeout;
    }

    /// Frames from the board that could not be decoded (garbage on the line), since connecting.
    pub fn bad_frames(&self) -> u64 {
        self.bad_frames
    }

    /// Telemetry records dropped because nobody read them, since connecting.
    pub fn telemetry_dropped(&self) -> u64 {
        self.telemetry_dropped
    }

    /// Sends a typed request and returns its reply: `board.call(GetStatus)` is a `Status`,
    /// `board.call(SetBus { .. })` a `()`.
    /// Crate-private: requests that move servos go through the typed methods, which take only
    /// what the rules made (`crate::rules`), so no door outside this crate can skip a rule.
    pub(crate) fn call<E: Endpoint>(&mut self, request: E) -> Result<E::Reply, LinkError> {
        self.request(&request.into())
    }

    /// Sends `request` and returns the reply's value of type `R`. A board still booting (it has
    /// just started, or just taken a gait with other servos, and is looking for them) refuses
    /// what needs the servos: such a request is retried for up to [`BOOT_WAIT`] on the
    /// transport's clock before the board's refusal is returned.
    pub(crate) fn request<R: Reply>(&mut self, request: &Request) -> Result<R, LinkError> {
        let name = request_name(request);
        let give_up = self.transport.now() + BOOT_WAIT;
        let response = loop {
            match self.request_response(request) {
                Err(LinkError::Device {
                    error:
                        ProtocolError::WrongState {
                            state: RunState::Boot,
                        },
                    ..
                }) if self.transport.now() < give_up => self.wait(Duration::from_millis(50))?,
                // Which fault, and on which joint: the refusal alone says only the state.
                Err(LinkError::Device {
                    error:
                        ProtocolError::WrongState {
                            state: RunState::Fault,
                        },
                    ..
                }) if !matches!(request, Request::GetStatus) => {
                    let fault = self.status().ok().and_then(|s| s.fault);
                    return Err(LinkError::Faulted {
                        port: self.port().to_owned(),
                        request: name,
                        fault,
                    });
                }
                r => break r?,
            }
        };
        let got = response.describe();
        R::from_response(response).ok_or_else(|| LinkError::Unexpected {
            port: self.port().to_owned(),
            request: name,
            got,
        })
    }

    /// Sends `request` and returns its [`Response`] (an error response becomes
    /// [`LinkError::Device`]).
    pub(crate) fn request_response(&mut self, request: &Request) -> Result<Response, LinkError> {
        let name = request_name(request);
        let (seq, frame) =
            self.client
                .request_frame(request)
                .map_err(|error| LinkError::Encode {
                    request: name,
                    error,
                })?;
        self.send_raw(&frame)?;
        let deadline = self.transport.now() + self.reply_timeout;
        loop {
            let Some(message) = self.next_message(deadline)? else {
                if let Some(f) = self.foreign.take()
                    && f.seq == seq
                {
                    return Err(LinkError::ProtocolVersion {
                        port: self.port().to_owned(),
                        board: f.protocol_version,
                        host: protocol::PROTOCOL_VERSION,
                    });
                }
                return Err(LinkError::NoReply {
                    port: self.port().to_owned(),
                    request: name,
                    timeout_ms: self.reply_timeout.as_millis() as u64,
                });
            };
            match message {
                DeviceMessage::Reply { seq: got, response } if got == seq => {
                    return match response {
                        Response::Error(error) => Err(LinkError::Device {
                            port: self.port().to_owned(),
                            request: name,
                            error,
                        }),
                        r => Ok(r),
                    };
                }
                // A late reply to an earlier request that timed out: not ours.
                DeviceMessage::Reply { .. } => {}
                DeviceMessage::Rejected(error) => {
                    return Err(LinkError::Rejected {
                        port: self.port().to_owned(),
                        request: name,
                        error,
                    });
                }
                DeviceMessage::Telemetry(t) => self.keep_telemetry(t),
                DeviceMessage::Proprioception(p) => self.keep_proprioception(p),
                // A refused streaming setpoint is not an answer to this request; the stream's
                // proprioception shows which setpoint the board last applied.
                DeviceMessage::SetpointRejected { .. } => {}
            }
        }
    }

    /// The next telemetry record, waiting up to `timeout` on the transport's clock.
    pub fn telemetry(&mut self, timeout: Duration) -> Result<Option<Telemetry>, LinkError> {
        if let Some(t) = self.telemetry.pop_front() {
            return Ok(Some(t));
        }
        let deadline = self.transport.now() + timeout;
        while let Some(message) = self.next_message(deadline)? {
            match message {
                DeviceMessage::Telemetry(t) => return Ok(Some(t)),
                DeviceMessage::Proprioception(p) => self.keep_proprioception(p),
                _ => {}
            }
        }
        Ok(None)
    }

    /// Drops telemetry received so far (e.g. before a recording starts).
    pub fn discard_telemetry(&mut self) {
        self.telemetry.clear();
    }

    pub fn status(&mut self) -> Result<Status, LinkError> {
        self.call(ep::GetStatus)
    }

    pub fn settings(&mut self) -> Result<Settings, LinkError> {
        self.call(ep::GetSettings)
    }

    pub fn gaits(&mut self) -> Result<Vec<SlotInfo>, LinkError> {
        let slots: heapless::Vec<SlotInfo, { protocol::MAX_SLOTS }> = self.call(ep::ListGaits)?;
        Ok(slots.into_iter().collect())
    }

    /// Servo IDs of the joints of the table in `slot`, or of the selected gait with `None`;
    /// `None` when the slot is empty or nothing is selected.
    pub fn joint_map(&mut self, slot: Option<u8>) -> Result<Option<protocol::JointIds>, LinkError> {
        self.call(ep::GetJointMap { slot })
    }

    /// Starts playback of a command the period rule passed (`rules::period::check_play`).
    pub fn play(&mut self, play: &CheckedPlay) -> Result<(), LinkError> {
        self.call(*play.command())
    }

    /// Lets `duration` pass on the transport's clock, keeping telemetry that arrives.
    pub fn wait(&mut self, duration: Duration) -> Result<(), LinkError> {
        let deadline = self.transport.now() + duration;
        while let Some(m) = self.next_message(deadline)? {
            match m {
                DeviceMessage::Telemetry(t) => self.keep_telemetry(t),
                DeviceMessage::Proprioception(p) => self.keep_proprioception(p),
                _ => {}
            }
        }
        Ok(())
    }

    pub fn stop(&mut self) -> Result<(), LinkError> {
        self.call(ep::Stop)
    }

    /// Queues a gait to play after the one playing, at a step boundary, without standing still
    /// (the board refuses one that cannot follow: `protocol::switch`, e.g. a joint jump beyond
    /// one bus cycle of its servo, naming the joint).
    /// The command is one the period rule passed (`rules::period::check_queue`).
    pub fn queue_gait(&mut self, queued: &CheckedQueue) -> Result<(), LinkError> {
        self.call(*queued.command())
    }

    /// Drops the queued gaits; the one playing plays on.
    pub fn clear_queue(&mut self) -> Result<(), LinkError> {
        self.call(ep::ClearQueue)
    }

    /// Sets the gaits [`Board::steer`] blends: slots `straight`, `left` and `right` (the gaits
    /// for headings 0, `+range_rad`, `-range_rad`), refused by the board with the reason if they
    /// cannot be blended (`protocol::steer`: slices, period, leg phases, joints, the switch rule).
    pub fn set_steer_family(
        &mut self,
        straight: u8,
        left: u8,
        right: u8,
        range_rad: f64,
    ) -> Result<(), LinkError> {
        let family = protocol::steer::family_of(straight, left, right, range_rad)
            .map_err(LinkError::Steer)?;
        self.steer_family = None;
        self.call(family)?;
        self.steer_family = Some(family);
        Ok(())
    }

    /// The steering family this host set with [`Board::set_steer_family`] and the board accepted
    /// (`None`: not set from this connection).
    pub fn steer_family(&self) -> Option<protocol::SteerFamily> {
        self.steer_family
    }

    /// The descending command: walk at `heading_rad` (positive left, within the family's range)
    /// and `speed` (1 = as planned). From standing the steered walk starts and goes on until
    /// [`Board::stop`]; while it walks, the new heading and speed take over at the next step
    /// boundary. Only a command the steering rule passed (`rules::steer::check_steer`: faster
    /// than planned, the family's tables against the servos).
    pub fn steer(&mut self, steer: &CheckedSteer) -> Result<(), LinkError> {
        self.call(*steer.command())
    }

    /// Sets up the perturbation platform for the next runs and waits (at most 1 s of the
    /// transport's clock) until the board has checked its servo: refused before sending when the
    /// set-up breaks `protocol::platform`'s rule against the board's joint map (an ID of a joint,
    /// positions outside a turn, a hold of 0), and an error naming the ID when the servo does not
    /// answer. `Board::play` is then refused by the board for a step beyond the run.
    pub fn set_platform(&mut self, setup: protocol::PlatformSetup) -> Result<(), LinkError> {
        let ids = self
            .joint_map(None)?
            .map(|m| m.servo_ids.to_vec())
            .unwrap_or_default();
        let refused = |port: &str, error| LinkError::Platform {
            port: port.to_owned(),
            error,
        };
        let port = self.port().to_owned();
        setup.check(&ids).map_err(|e| refused(&port, e))?;
        self.call(setup)?;
        for _ in 0..100 {
            let status = self.platform()?;
            match status.map(|p| p.state) {
                Some(protocol::PlatformState::Ready { .. }) => return Ok(()),
                Some(protocol::PlatformState::NotAnswering) => {
                    return Err(refused(
                        &port,
                        protocol::PlatformError::NotAnswering {
                            servo_id: setup.servo_id,
                        },
                    ));
                }
                Some(protocol::PlatformState::Checking) | None => {
                    self.wait(Duration::from_millis(10))?
                }
            }
        }
        Err(refused(
            &port,
            protocol::PlatformError::Checking {
                servo_id: setup.servo_id,
            },
        ))
    }

    /// No platform any more.
    pub fn clear_platform(&mut self) -> Result<(), LinkError> {
        self.call(ep::ClearPlatform)
    }

    /// The platform set up and its servo's state (`None`: none).
    pub fn platform(&mut self) -> Result<Option<protocol::PlatformStatus>, LinkError> {
        self.call(ep::GetPlatform)
    }

    pub fn emergency_stop(&mut self) -> Result<(), LinkError> {
        self.call(ep::EmergencyStop)
    }

    pub fn clear_fault(&mut self) -> Result<(), LinkError> {
        self.call(ep::ClearFault)
    }

    pub fn set_torque(&mut self, servos: ServoSelect, enable: bool) -> Result<(), LinkError> {
        self.call(ep::SetTorque { servos, enable })
    }

    /// Heat and supply limits (checked on the board too: `InvalidSetting` "health limits").
    /// Reads `read.len` bytes at `read.addr` of servo `read.id` on the board's bus (a Ping with
    /// length 0), through the board: asked, then collected once a bus cycle had the time for it,
    /// for at most `timeout` of the transport's clock. `None`: not done by then (a board busy
    /// with long bus cycles, or gone quiet).
    pub fn read_servo(
        &mut self,
        read: protocol::ServoRead,
        timeout: Duration,
    ) -> Result<Option<protocol::ServoReadOutcome>, LinkError> {
        self.call(read)?;
        let deadline = self.transport.now() + timeout;
        loop {
            if let Some(r) = self.call(ep::GetServoRead)?
                && r.request == read
            {
                return Ok(Some(r.outcome));
            }
            if self.transport.now() >= deadline {
                return Ok(None);
            }
            // A bus cycle or so (10 ms at 100 Hz): the read is done after one.
            self.wait(Duration::from_millis(5))?;
        }
    }

    pub fn set_health_limits(&mut self, limits: protocol::HealthLimits) -> Result<(), LinkError> {
        self.call(limits)
    }

    pub fn set_telemetry(&mut self, every: u16) -> Result<(), LinkError> {
        self.call(ep::SetTelemetry { every })
    }

    /// Bus baud (bit/s) and cycle rate (Hz), unchecked: crate-private, every door changes the
    /// bus through `rules::bus::set_bus`, which verifies the servos follow a baud change.
    pub(crate) fn set_bus(&mut self, baud: u32, cycle_hz: u16) -> Result<(), LinkError> {
        self.call(ep::SetBus { baud, cycle_hz })
    }

    /// Stiffness of `joint`, mN m/rad: the board writes it to the servo's Position P Gain and the
    /// torque bias divides by it (0: bias off, the gain left as it is).
    /// Only a stiffness the rule passed (`rules::stiffness::Stiffness`: the board's unit and
    /// every servo's P gain register); the board checks the joint's own servo again.
    pub fn set_stiffness(&mut self, joint: u8, stiffness: Stiffness) -> Result<(), LinkError> {
        self.call(ep::SetStiffness {
            joint,
            stiffness: stiffness.units(),
        })
    }

    pub(super) fn send_raw(&mut self, bytes: &[u8]) -> Result<(), LinkError> {
        self.transport
            .send(bytes)
            .map_err(|source| vanished(self.transport.name(), source))
    }

    /// The next decoded message, reading until `deadline` on the transport's clock. Ends early
    /// (with `None`) at a `DeviceInfo` reply of another protocol version, left in `self.foreign`.
    pub(super) fn next_message(
        &mut self,
        deadline: Duration,
    ) -> Result<Option<DeviceMessage>, LinkError> {
        loop {
            if let Some(m) = self.inbox.pop_front() {
                return Ok(Some(m));
            }
            let now = self.transport.now();
            if now >= deadline || self.foreign.is_some() {
                return Ok(None);
            }
            let n = self
                .transport
                .recv(&mut self.rx[..], deadline - now)
                .map_err(|source| vanished(self.transport.name(), source))?;
            // The whole chunk at once (the accumulator copies a block's data in one piece): the
            // same frames as byte by byte, for less time per byte.
            let mut input = &self.rx[..n];
            while let Some(frame) = self.acc.push_slice(&mut input) {
                let Ok(frame) = frame else {
                    self.bad_frames += 1;
                    continue;
                };
                match protocol::decode_message::<DeviceMessage>(frame) {
                    Ok(m) => self.inbox.push_back(m),
                    Err(_) => {
                        self.bad_frames += 1;
                        if let Some(f) = device_info_prefix(frame) {
                            self.foreign = Some(f);
                        }
                    }
                }
            }
        }
    }

    pub(super) fn keep_telemetry(&mut self, t: Telemetry) {
        if self.telemetry.len() >= TELEMETRY_BACKLOG {
            self.telemetry.pop_front();
            self.telemetry_dropped += 1;
        }
        self.telemetry.push_back(t);
    }
}

fn vanished(port: &str, source: TransportError) -> LinkError {
    LinkError::Vanished {
        port: port.to_owned(),
        source,
    }
}

/// Stands in until the board has answered `GetDeviceInfo`.
fn placeholder_info() -> DeviceInfo {
    DeviceInfo {
        firmware: protocol::FirmwareVersion {
            major: 0,
            minor: 0,
            patch: 0,
        },
        protocol_version: 0,
        table_format_version: 0,
        build_id: 0,
        capabilities: protocol::Capabilities::empty(),
        slot_capacity: 0,
        max_chunk_len: 0,
        slots: heapless::Vec::new(),
    }
}

/// A short name of a request for messages (the protocol's endpoint name).
pub fn request_name(request: &Request) -> &'static str {
    request.name()
}

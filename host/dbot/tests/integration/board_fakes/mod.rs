//! Fakes behind a pseudo-terminal for the board-facing `dbot` tests
//! (host/dbot/tests/integration/reliability_board_cli.rs): a pty nobody answers, a board that answers only
//! `GetDeviceInfo` (with any protocol version) and records every byte it receives, and the
//! virtual robot served in real time, as a board on USB would be.
#![allow(dead_code)]

pub mod cli;

use std::fs::File;
use std::io::{Read, Write};
use std::os::fd::{AsFd, AsRawFd, OwnedFd};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::Instant;

use board::link::Board;
use board::robot::{VirtualRobot, VirtualTransport};
use firmware::safety::State;
use nix::fcntl::{FcntlArg, FdFlag, fcntl};
use nix::poll::{PollFd, PollFlags, PollTimeout, poll};
use nix::pty::openpty;
use nix::sys::termios::{SetArg, cfmakeraw, tcgetattr, tcsetattr};
use protocol::{DeviceInfo, DeviceMessage, FrameAccumulator, HostMessage, Request, Response};

/// A pseudo-terminal: `path` is what `dbot --port` opens. The test keeps the slave open too, so
/// the master never sees a hang-up when `dbot` closes its end.
pub struct Pty {
    pub master: File,
    pub slave: OwnedFd,
    pub path: String,
}

pub fn pty() -> Pty {
    let p = openpty(None, None).unwrap();
    // Not inherited by the `dbot` processes the tests spawn.
    for fd in [&p.master, &p.slave] {
        fcntl(fd.as_fd(), FcntlArg::F_SETFD(FdFlag::FD_CLOEXEC)).unwrap();
    }
    let path = nix::unistd::ttyname(p.slave.as_fd())
        .unwrap()
        .to_string_lossy()
        .into_owned();
    let mut t = tcgetattr(p.slave.as_fd()).unwrap();
    cfmakeraw(&mut t);
    tcsetattr(p.slave.as_fd(), SetArg::TCSANOW, &t).unwrap();
    Pty {
        master: File::from(p.master),
        slave: p.slave,
        path,
    }
}

/// Reads what is there within `ms` milliseconds (empty if nothing came).
fn read_some(master: &mut File, ms: u16) -> Vec<u8> {
    let mut fds = [PollFd::new(master.as_fd(), PollFlags::POLLIN)];
    match poll(&mut fds, PollTimeout::from(ms)) {
        Ok(n) if n > 0 => {}
        _ => return Vec::new(),
    }
    let mut buf = [0u8; 4096];
    match master.read(&mut buf) {
        Ok(n) => buf[..n].to_vec(),
        Err(_) => Vec::new(),
    }
}

/// The `DeviceInfo` of a board that speaks `protocol_version` (otherwise like the virtual robot's).
pub fn device_info(protocol_version: u16) -> DeviceInfo {
    DeviceInfo {
        firmware: protocol::FirmwareVersion {
            major: 0,
            minor: 9,
            patch: 0,
        },
        protocol_version,
        table_format_version: protocol::gait::FORMAT_VERSION,
        build_id: 0x1234_5678,
        capabilities: protocol::Capabilities::empty(),
        slot_capacity: 64 * 1024,
        max_chunk_len: 256,
        slots: heapless::Vec::new(),
    }
}

/// How the fake board answers `GetDeviceInfo`.
#[derive(Debug, Clone, Copy)]
pub enum Answer {
    /// A `DeviceInfo` with this protocol version, encoded by the protocol crate.
    Version(u16),
    /// The same followed by 6 bytes of fields this host does not know (a later protocol version
    /// that added fields), so the whole reply does not decode here.
    VersionWithNewFields(u16),
    /// This host's protocol version, but this gait table format version.
    TableFormat(u16),
}

/// A board that answers `GetDeviceInfo` only and keeps every byte it received.
pub struct FakeBoard {
    pub pty_path: String,
    stop: Arc<AtomicBool>,
    handle: JoinHandle<Vec<u8>>,
}

impl FakeBoard {
    pub fn start(answer: Answer) -> Self {
        let mut p = pty();
        let pty_path = p.path.clone();
        let stop = Arc::new(AtomicBool::new(false));
        let stop2 = stop.clone();
        let handle = std::thread::spawn(move || {
            let _slave = p.slave;
            let mut received = Vec::new();
            let mut acc = FrameAccumulator::new();
            while !stop2.load(Ordering::Relaxed) {
                let bytes = read_some(&mut p.master, 10);
                received.extend_from_slice(&bytes);
                for &b in &bytes {
                    let Some(Ok(HostMessage::Request {
                        seq,
                        request: Request::GetDeviceInfo,
                    })) = acc.push_message::<HostMessage>(b)
                    else {
                        continue;
                    };
                    let mut info = device_info(protocol::PROTOCOL_VERSION);
                    let extra = match answer {
                        Answer::Version(v) => {
                            info.protocol_version = v;
                            false
                        }
                        Answer::VersionWithNewFields(v) => {
                            info.protocol_version = v;
                            true
                        }
                        Answer::TableFormat(v) => {
                            info.table_format_version = v;
                            false
                        }
                    };
                    let reply = DeviceMessage::Reply {
                        seq,
                        response: Response::DeviceInfo(info),
                    };
                    let frame = if extra {
                        // Postcard encodes a tuple as its fields in order: the reply, then more.
                        protocol::frame::encode_frame_vec(&(reply, 0xABCD_EF01u32, 7u16)).unwrap()
                    } else {
                        protocol::frame::encode_frame_vec(&reply).unwrap()
                    };
                    p.master.write_all(&frame).unwrap();
                }
            }
            received
        });
        Self {
            pty_path,
            stop,
            handle,
        }
    }

    /// Stops the board; returns every byte it received.
    pub fn finish(self) -> Vec<u8> {
        self.stop.store(true, Ordering::Relaxed);
        self.handle.join().unwrap()
    }
}

/// The host messages in `bytes` (frames that do not decode are returned as `None`).
pub fn host_messages(bytes: &[u8]) -> Vec<Option<HostMessage>> {
    let mut acc = FrameAccumulator::new();
    bytes
        .iter()
        .filter_map(|&b| acc.push_message::<HostMessage>(b))
        .map(|r| r.ok())
        .collect()
}

/// The virtual robot served on a pty in real time (its clock follows the wall clock), so that its
/// state can be watched from the test while `dbot` drives it as it would a board on USB.
pub struct RobotServer {
    pub pty_path: String,
    state: Arc<Mutex<State>>,
    stop: Arc<AtomicBool>,
    handle: JoinHandle<()>,
}

impl RobotServer {
    /// A robot whose slot 0 holds `table` (uploaded in-process before serving).
    pub fn start(table: Vec<u8>) -> Self {
        let mut p = pty();
        let pty_path = p.path.clone();
        let stop = Arc::new(AtomicBool::new(false));
        let state = Arc::new(Mutex::new(State::Boot));
        let (stop2, state2) = (stop.clone(), state.clone());
        // Non-blocking writes: once dbot is gone nobody drains the pty, and the robot's telemetry
        // must not block the server.
        fcntl(
            p.master.as_fd(),
            FcntlArg::F_SETFL(nix::fcntl::OFlag::O_NONBLOCK),
        )
        .unwrap();
        let handle = std::thread::spawn(move || {
            let _slave = p.slave;
            let mut b = Board::connect(VirtualTransport::new(VirtualRobot::new())).unwrap();
            gate::upload(&mut b, 0, &table).unwrap();
            let mut robot = b.into_transport().into_robot();
            let (t0, base) = (Instant::now(), robot.now_us());
            let mut out = [0u8; 4096];
            // Bytes for the host not yet taken by the pty: kept, as a USB link's flow control
            // would (telemetry piles up while dbot draws its plots), up to a bound for when dbot
            // is gone for good.
            let mut outbox: Vec<u8> = Vec::new();
            while !stop2.load(Ordering::Relaxed) {
                let bytes = read_some(&mut p.master, 1);
                if !bytes.is_empty() {
                    robot.receive(&bytes);
                }
                // Small steps of simulated time keep requests answered promptly when the
                // simulation runs behind the wall clock on a loaded machine.
                let wall = base + t0.elapsed().as_micros() as u64;
                robot.run_until(wall.min(robot.now_us() + 20_000));
                while robot.pending() > 0 {
                    let n = robot.take(&mut out);
                    outbox.extend_from_slice(&out[..n]);
                }
                while !outbox.is_empty() {
                    match p.master.write(&outbox) {
                        Ok(n) if n > 0 => drop(outbox.drain(..n)),
                        _ => break,
                    }
                }
                if outbox.len() > 16 << 20 {
                    outbox.clear();
                }
                *state2.lock().unwrap() = robot.controller().state();
            }
        });
        Self {
            pty_path,
            state,
            stop,
            handle,
        }
    }

    /// The controller's state now.
    pub fn state(&self) -> State {
        *self.state.lock().unwrap()
    }

    pub fn finish(self) {
        self.stop.store(true, Ordering::Relaxed);
        self.handle.join().unwrap();
    }
}

/// The raw fd of a pty's slave (to change its mode in a permission test).
pub fn slave_fd(p: &Pty) -> i32 {
    p.slave.as_raw_fd()
}

pub use crate::gate;

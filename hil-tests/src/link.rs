//! A test's own connection to the board's USB serial port (the emulator's pty or `/dev/ttyACM0`):
//! protocol frames in and out, with wall-clock timeouts, and raw bytes for the robustness tests
//! (garbage, oversized frames). Telemetry and other unsolicited messages that arrive while a test
//! waits for a reply are kept in [`Link::unsolicited`] in arrival order.

use anyhow::{Context, Result, anyhow, bail};
use nix::poll::{PollFd, PollFlags, PollTimeout, poll};
use nix::sys::termios::{SetArg, cfmakeraw, tcgetattr, tcsetattr};
use protocol::client::{Client, Reply, reply};
use protocol::frame::FrameAccumulator;
use protocol::{DeviceMessage, Request};
use std::collections::VecDeque;
use std::fs::File;
use std::io::{Read, Write};
use std::os::fd::AsFd;
use std::path::Path;
use std::time::{Duration, Instant};

/// An open link to the board.
#[derive(Debug)]
pub struct Link {
    port: File,
    client: Client,
    acc: FrameAccumulator,
    /// Device messages that were not the awaited reply (telemetry, proprioception, rejections).
    pub unsolicited: VecDeque<DeviceMessage>,
    /// Frames from the board that did not decode (a board bug or a corrupted link).
    pub undecodable: usize,
}

impl Link {
    /// Opens the port in raw mode.
    pub fn open(port: &Path) -> Result<Self> {
        let file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .open(port)
            .with_context(|| format!("cannot open {}", port.display()))?;
        let mut t = tcgetattr(file.as_fd()).context("tcgetattr")?;
        cfmakeraw(&mut t);
        tcsetattr(file.as_fd(), SetArg::TCSANOW, &t).context("tcsetattr")?;
        Ok(Self {
            port: file,
            client: Client::new(),
            acc: FrameAccumulator::new(),
            unsolicited: VecDeque::new(),
            undecodable: 0,
        })
    }

    /// Writes bytes as they are (no framing).
    pub fn send_raw(&mut self, bytes: &[u8]) -> Result<()> {
        self.port.write_all(bytes).context("write to the board")?;
        self.port.flush()?;
        Ok(())
    }

    /// Sends a request and returns its sequence number.
    pub fn send(&mut self, request: &Request) -> Result<u16> {
        let (seq, frame) = self
            .client
            .request_frame(request)
            .map_err(|e| anyhow!("cannot encode {request:?}: {e:?}"))?;
        self.send_raw(&frame)?;
        Ok(seq)
    }

    /// Sends a request and waits for its reply, converted to `R` (errors from the board included).
    pub fn request<R: Reply>(&mut self, request: &Request, timeout: Duration) -> Result<R> {
        let seq = self.send(request)?;
        self.reply(seq, timeout)
            .with_context(|| format!("request {request:?}"))
    }

    /// Waits for the reply to `seq`; other messages go to `unsolicited`.
    pub fn reply<R: Reply>(&mut self, seq: u16, timeout: Duration) -> Result<R> {
        let deadline = Instant::now() + timeout;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            let Some(msg) = self.next_message(left)? else {
                bail!("no reply to request #{seq} within {timeout:?}");
            };
            match msg {
                DeviceMessage::Reply { seq: got, .. } if got == seq => {
                    return reply(seq, msg).map_err(|e| anyhow!("board answered #{seq}: {e:?}"));
                }
                other => self.unsolicited.push_back(other),
            }
        }
    }

    /// The next message from the board, or `None` after `timeout` of silence.
    pub fn next_message(&mut self, timeout: Duration) -> Result<Option<DeviceMessage>> {
        let deadline = Instant::now() + timeout;
        let mut byte = [0u8; 1];
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            let ms = u16::try_from(left.as_millis()).unwrap_or(u16::MAX);
            let mut fds = [PollFd::new(self.port.as_fd(), PollFlags::POLLIN)];
            if poll(&mut fds, PollTimeout::from(ms)).context("poll on the port")? == 0 {
                return Ok(None);
            }
            // Byte by byte: the accumulator borrows its buffer per frame.
            if self.port.read(&mut byte).context("read from the board")? == 0 {
                bail!("the board's port closed");
            }
            match self.acc.push_message::<DeviceMessage>(byte[0]) {
                Some(Ok(m)) => return Ok(Some(m)),
                Some(Err(_)) => self.undecodable += 1,
                None => {}
            }
        }
    }

    /// Collects every message that arrives within `window`.
    pub fn collect(&mut self, window: Duration) -> Result<Vec<DeviceMessage>> {
        let deadline = Instant::now() + window;
        let mut out: Vec<_> = self.unsolicited.drain(..).collect();
        while let Some(m) = self.next_message(deadline.saturating_duration_since(Instant::now()))? {
            out.push(m);
        }
        Ok(out)
    }
}

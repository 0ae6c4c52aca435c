//! The host link: COBS frames of the protocol crate in, replies and telemetry out. The dispatcher
//! ([`Link`]) is synchronous and holds no I/O; [`serve`] runs it over any
//! `embedded_io_async::{Read, Write}` (USB CDC-ACM on the board, an in-memory pipe in tests). When
//! the link drops, only the partial frame is forgotten: the controller, a running gait and an upload
//! in progress carry on, and the host resumes where it was.

pub(crate) mod convert;
mod dispatch;
mod down;
#[cfg(test)]
mod store_tests;
#[cfg(test)]
mod tests;

use dynamixel::master::{Clock, with_deadline};
use embedded_io_async::{Read, Write};
use embedded_storage::nor_flash::NorFlash;
use protocol::{DeviceMessage, FrameAccumulator, HostMessage, MAX_FRAME_LEN, UploadTracker};

use crate::bus_loop::Shared;
use crate::controller::Controller;
use crate::store::FlashWindow;

pub use down::LinkDown;

/// How long [`serve`] waits for host bytes before it looks for telemetry to send, microseconds.
pub const POLL_US: u64 = 2_000;
/// How long a frame may take to leave before the host counts as not reading: the frame is given up
/// (the host's accumulator drops the cut frame at the next delimiter) and serving goes on.
pub const WRITE_TIMEOUT_US: u64 = 50_000;

/// The protocol dispatcher: frame reassembly, the upload rules, requests to the controller.
#[derive(Debug)]
pub struct Link {
    frames: FrameAccumulator,
    upload: UploadTracker,
    /// Frames that could not be decoded.
    pub rejected: u32,
    tx: [u8; MAX_FRAME_LEN],
}

impl Default for Link {
    fn default() -> Self {
        Self::new()
    }
}

impl Link {
    pub const fn new() -> Self {
        Self {
            frames: FrameAccumulator::new(),
            upload: UploadTracker::new(),
            rejected: 0,
            tx: [0; MAX_FRAME_LEN],
        }
    }

    /// The link dropped: a partial frame is garbage now.
    pub fn reset(&mut self) {
        self.frames.reset();
    }

    /// Takes received bytes; each complete frame is handled and its answer (if any) passed to `send`
    /// as an encoded frame.
    pub fn receive<S, F>(&mut self, shared: &S, bytes: &[u8], send: &mut impl FnMut(&[u8]))
    where
        S: Shared<Controller<F>>,
        F: NorFlash + FlashWindow,
    {
        for &b in bytes {
            let message = match self.frames.push(b) {
                None => continue,
                Some(Ok(frame)) => protocol::decode_message::<HostMessage>(frame),
                Some(Err(e)) => Err(e),
            };
            let answer = match message {
                Ok(HostMessage::Request { seq, request }) => {
                    let rejected = self.rejected;
                    let response = shared
                        .with(|c| self::dispatch::handle(&mut self.upload, c, request, rejected));
                    Some(DeviceMessage::Reply { seq, response })
                }
                Ok(HostMessage::Setpoint(sp)) => {
                    shared.with(|c| self::dispatch::setpoint(c, &sp));
                    None
                }
                Err(e) => {
                    self.rejected = self.rejected.wrapping_add(1);
                    Some(DeviceMessage::Rejected(e))
                }
            };
            if let Some(m) = answer
                && let Ok(frame) = protocol::encode_frame(&m, &mut self.tx)
            {
                send(frame);
            }
        }
    }

    /// The next telemetry record as an encoded frame (`Telemetry`, or `Proprioception` while
    /// streaming), if the controller has one.
    pub fn telemetry<S, F>(&mut self, shared: &S) -> Option<&[u8]>
    where
        S: Shared<Controller<F>>,
        F: NorFlash + FlashWindow,
    {
        let message = shared.with(|c| {
            let record = c.pop_telemetry()?;
            Some(convert::telemetry(c, &record))
        })?;
        protocol::encode_frame(&message, &mut self.tx).ok()
    }
}

/// Why [`serve`] returned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LinkEnd {
    /// Reading or writing failed: the host went away.
    Dropped,
}

/// Serves the host over `io` until the link drops: answers requests as they come and sends queued
/// telemetry in between. The bus loop never waits for this task; when the host is slow, telemetry is
/// dropped in the controller's queue.
pub async fn serve<S, F, IO, C>(link: &mut Link, shared: &S, io: &mut IO, clock: &C) -> LinkEnd
where
    S: Shared<Controller<F>>,
    F: NorFlash + FlashWindow,
    IO: Read + Write,
    C: Clock,
{
    let mut rx = [0u8; 64];
    loop {
        let deadline = clock.now_us() + POLL_US;
        match with_deadline(clock, deadline, io.read(&mut rx)).await {
            Some(Ok(0)) | Some(Err(_)) => {
                link.reset();
                return LinkEnd::Dropped;
            }
            Some(Ok(n)) => {
                let mut out = OutQueue::new();
                link.receive(shared, &rx[..n], &mut |frame| out.push(frame));
                for frame in out.frames() {
                    if send(io, clock, frame).await.is_err() {
                        link.reset();
                        return LinkEnd::Dropped;
                    }
                }
            }
            None => {}
        }
        while let Some(frame) = link.telemetry(shared) {
            match send(io, clock, frame).await {
                Ok(true) => {}
                // Host not reading: leave the rest queued (and dropped by the controller).
                Ok(false) => break,
                Err(()) => {
                    link.reset();
                    return LinkEnd::Dropped;
                }
            }
        }
        let deadline = clock.now_us() + WRITE_TIMEOUT_US;
        if let Some(Err(_)) = with_deadline(clock, deadline, io.flush()).await {
            link.reset();
            return LinkEnd::Dropped;
        }
    }
}

/// Writes one frame: `Ok(true)` sent, `Ok(false)` timed out (host not reading), `Err` link down.
async fn send<IO: Write, C: Clock>(io: &mut IO, clock: &C, frame: &[u8]) -> Result<bool, ()> {
    let deadline = clock.now_us() + WRITE_TIMEOUT_US;
    match with_deadline(clock, deadline, io.write_all(frame)).await {
        Some(Ok(())) => Ok(true),
        Some(Err(_)) => Err(()),
        None => Ok(false),
    }
}

/// Replies produced by one read, kept until they are written (a read of 64 bytes holds at most a
/// few small requests; anything past the buffer is dropped and the host times out and retries).
struct OutQueue {
    buf: [u8; 2 * MAX_FRAME_LEN],
    len: usize,
    ends: heapless::Vec<usize, 16>,
}

impl OutQueue {
    fn new() -> Self {
        Self {
            buf: [0; 2 * MAX_FRAME_LEN],
            len: 0,
            ends: heapless::Vec::new(),
        }
    }

    fn push(&mut self, frame: &[u8]) {
        let end = self.len + frame.len();
        if end <= self.buf.len() && self.ends.push(end).is_ok() {
            self.buf[self.len..end].copy_from_slice(frame);
            self.len = end;
        }
    }

    fn frames(&self) -> impl Iterator<Item = &[u8]> {
        let mut start = 0;
        self.ends.iter().map(move |&end| {
            let f = &self.buf[start..end];
            start = end;
            f
        })
    }
}

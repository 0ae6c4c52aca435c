//! A simulated half-duplex wire on a simulated clock, master side: [`SimWire`] implements
//! `embedded_io_async::{Read, Write}` and [`Clock`], so a [`crate::master::BusMaster`] runs
//! against a [`VirtualChain`] deterministically and much faster than real time.
//!
//! Timing: each byte takes 10 bit times at the configured baud; the master's bytes queue behind
//! each other on the wire; a servo executes a request when its last byte has arrived, and its
//! reply starts after its Return Delay Time (chained replies: after the previous reply's end).
//! With `echo` the master hears its own bytes as they leave (shared TX/RX wire). `flush`
//! resolves when the last written byte has left the wire, like `tcdrain` on a host UART.
//!
//! Time advances only in [`SimWire::block_on`] (a tiny executor): whenever the future is pending
//! it jumps to the next event (a byte reaching the master or a servo, or the earliest deadline
//! the future waits for). Physics time follows simulated time: the motors are stepped to the
//! current time before a servo executes a request and before [`SimWire::with_chain`] hands out
//! the chain; [`SimWire::advance_us`] moves time (and physics) on with no bus activity.

use super::chain::VirtualChain;
use crate::master::Clock;
use crate::parser::Parser;
use core::future::Future;
use core::pin::pin;
use core::task::{Context, Poll, Waker};
use std::cell::RefCell;
use std::collections::VecDeque;
use std::rc::Rc;

/// A servo drops a half-received packet after this much silence (e-manual: 1.5 ms).
const INTER_BYTE_TIMEOUT_NS: u64 = 1_500_000;

/// Which byte arrivals at the servos [`State::hear`] processes.
#[derive(Debug, Clone, Copy)]
enum Heard {
    /// Those before the time, or all when there is none.
    Before(Option<u64>),
    /// Those at or before the time.
    UpTo(u64),
}

impl Heard {
    fn holds(self, at_ns: u64) -> bool {
        match self {
            Heard::Before(limit) => limit.is_none_or(|l| at_ns < l),
            Heard::UpTo(t) => at_ns <= t,
        }
    }
}

/// Wire settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WireConfig {
    /// Line rate in bit/s.
    pub baud: u32,
    /// The master hears its own bytes (TX and RX on one wire).
    pub echo: bool,
}

#[derive(Debug)]
struct State {
    now_ns: u64,
    physics_ns: u64,
    chain: VirtualChain,
    config: WireConfig,
    /// Master -> servos bytes with the time their stop bit ends.
    to_servos: VecDeque<(u64, u8)>,
    /// Servos (and echo) -> master.
    to_master: VecDeque<(u64, u8)>,
    /// When the master's last queued byte has left.
    master_tx_end_ns: u64,
    /// When the last reply queued ends (for chained replies).
    reply_end_ns: u64,
    servo_parser: Parser<1024>,
    last_servo_byte_ns: u64,
    /// Earliest deadline a pending future waits for (reset before each poll).
    timer_ns: Option<u64>,
    /// The last byte of the burst toward the master that [`SimWire::block_on`] found, kept
    /// while the bytes queued toward the master leave it so or extend it
    /// ([`State::queue_to_master`]; the burst's end is the same from any of its bytes, and
    /// finding it again was most of the executor's own time).
    burst_end_ns: Option<u64>,
    bytes_to_servos: u64,
    bytes_to_master: u64,
}

/// Master end of the simulated bus. Cheap to clone; clones share the wire, the clock and the chain.
#[derive(Debug, Clone)]
pub struct SimWire {
    state: Rc<RefCell<State>>,
}

/// Simulated-time error type of the wire (it never fails).
pub type SimIoError = core::convert::Infallible;

impl SimWire {
    pub fn new(chain: VirtualChain, config: WireConfig) -> Self {
        let state = State {
            now_ns: 0,
            physics_ns: 0,
            chain,
            config,
            to_servos: VecDeque::new(),
            to_master: VecDeque::new(),
            master_tx_end_ns: 0,
            reply_end_ns: 0,
            servo_parser: Parser::new(),
            last_servo_byte_ns: 0,
            timer_ns: None,
            burst_end_ns: None,
            bytes_to_servos: 0,
            bytes_to_master: 0,
        };
        Self {
            state: Rc::new(RefCell::new(state)),
        }
    }

    /// Simulated time in microseconds.
    pub fn now_us(&self) -> u64 {
        self.state.borrow().now_ns / 1_000
    }

    /// Bytes sent by the master and by the servos so far.
    pub fn byte_counts(&self) -> (u64, u64) {
        let s = self.state.borrow();
        (s.bytes_to_servos, s.bytes_to_master)
    }

    /// Puts `bytes` on the wire toward the master, starting now at the wire's byte rate (noise,
    /// a glitch, another device talking): for testing resynchronisation.
    pub fn inject_noise(&self, bytes: &[u8]) {
        let mut s = self.state.borrow_mut();
        let byte_ns = s.byte_ns();
        let start = s.now_ns;
        s.queue_to_master(start, byte_ns, bytes);
    }

    /// Changes the line rate (after the servos were told to switch).
    pub fn set_baud(&self, baud: u32) {
        let mut s = self.state.borrow_mut();
        s.config.baud = baud;
        s.burst_end_ns = None;
    }

    /// The chain with its motors stepped to the current time: set external torques, faults, read state.
    pub fn with_chain<R>(&self, f: impl FnOnce(&mut VirtualChain) -> R) -> R {
        let mut s = self.state.borrow_mut();
        let now = s.now_ns;
        s.step_physics(now);
        f(&mut s.chain)
    }

    /// Moves simulated time on by `dt_us`, processing bus events on the way.
    pub fn advance_us(&self, dt_us: u64) {
        let mut s = self.state.borrow_mut();
        let target = s.now_ns + dt_us * 1_000;
        s.run_until(target);
        s.step_physics(target);
    }

    /// Runs `fut` to completion on simulated time.
    ///
    /// # Panics
    /// If the future is pending while no bus event and no deadline can ever wake it (a bug in the
    /// test: e.g. a read without a timeout while no servo will answer).
    pub fn block_on<F: Future>(&self, fut: F) -> F::Output {
        let mut fut = pin!(fut);
        let mut cx = Context::from_waker(Waker::noop());
        loop {
            self.state.borrow_mut().timer_ns = None;
            if let Poll::Ready(v) = fut.as_mut().poll(&mut cx) {
                return v;
            }
            let mut s = self.state.borrow_mut();
            // A burst of bytes back to back toward the master (a reply, a chain of replies, the
            // master's own echo) wakes the future once, at its last byte, instead of once per
            // byte: the bytes keep their times, so the master sees the same bytes by then. Bytes
            // reaching the servos inside the burst are processed without waking the future
            // unless a servo queues a reply (then the future looks at once, as before); a
            // deadline ends the burst early. Waking per echoed byte was most of the executor's
            // time in the physics robot (docs/performance.md).
            // Only future events: bytes already due may sit unread while the future waits on a timer.
            let now = s.now_ns;
            let next_to_master = match s.burst_end_ns {
                Some(end) if end > now => Some(end),
                _ => {
                    let end = s.burst_end(now);
                    s.burst_end_ns = end;
                    end
                }
            };
            // The burst's end stays the same while the servos hear bytes and queue no reply.
            let wake = [next_to_master, s.timer_ns].into_iter().flatten().min();
            // The servos hear the bytes due before the wake-up; a reply they queue wakes the
            // future at once (at the time of the byte that completed the request).
            if s.hear(Heard::Before(wake), true) {
                continue;
            }
            match wake {
                Some(t) => s.run_until(t),
                None => panic!(
                    "simulated bus: the future waits for nothing that can happen (no byte in flight, no deadline)"
                ),
            }
        }
    }
}

impl State {
    fn byte_ns(&self) -> u64 {
        10_000_000_000 / self.config.baud as u64
    }

    /// Queues `bytes` toward the master back to back, the first ending `byte_ns` after
    /// `start_ns`, and keeps the queue in time order: the bytes of one call are in order among
    /// themselves, so only when the first comes before the byte queued last is the queue sorted
    /// again (a stable sort, as before; replies after their request's echo never need it).
    ///
    /// The burst end found last ([`SimWire::block_on`]) is kept when it still holds: bytes that
    /// come in order after a later burst, or after a gap, leave the first burst as it was;
    /// bytes that continue it (within a byte time of its end, the queue's last byte) extend it
    /// to their last. Finding it again meant walking every reply byte of a Sync Read.
    fn queue_to_master(&mut self, start_ns: u64, byte_ns: u64, bytes: &[u8]) {
        if bytes.is_empty() {
            return;
        }
        let first = start_ns + byte_ns;
        let last = start_ns + bytes.len() as u64 * byte_ns;
        let back = self.to_master.back().map(|b| b.0);
        let in_order = back.is_none_or(|b| b <= first);
        self.burst_end_ns = match (self.burst_end_ns, back) {
            (Some(end), Some(b)) if in_order && (end < b || first > end + byte_ns) => Some(end),
            (Some(end), Some(b)) if in_order && end == b => Some(last),
            _ => None,
        };
        self.to_master.extend(
            bytes
                .iter()
                .enumerate()
                .map(|(i, &b)| (start_ns + (i as u64 + 1) * byte_ns, b)),
        );
        if !in_order {
            self.to_master.make_contiguous().sort_by_key(|b| b.0);
        }
    }

    /// The last byte of the first burst toward the master after `now_ns` (bytes back to back).
    fn burst_end(&self, now_ns: u64) -> Option<u64> {
        let byte_ns = self.byte_ns();
        let mut end = None;
        let first = self.to_master.partition_point(|b| b.0 <= now_ns);
        for t in self.to_master.range(first..).map(|b| b.0) {
            match end {
                Some(e) if t > e + byte_ns => break,
                _ => end = Some(t),
            }
        }
        end
    }

    fn step_physics(&mut self, to_ns: u64) {
        if to_ns > self.physics_ns {
            self.chain.step((to_ns - self.physics_ns) as f64 * 1e-9);
            self.physics_ns = to_ns;
        }
    }

    /// Processes every byte arrival at the servos up to `t_ns`, then sets the clock to `t_ns`.
    fn run_until(&mut self, t_ns: u64) {
        self.hear(Heard::UpTo(t_ns), false);
        self.now_ns = self.now_ns.max(t_ns);
    }

    /// The servos hear the bytes arriving in `heard`, each at its time (the clock follows them);
    /// with `stop_at_reply`, only until a byte makes a servo queue a reply: then true.
    ///
    /// Inside a packet whose length is known, the bytes before its last cannot complete it
    /// (`Parser::quiet_bytes`): they are buffered as they come, without the per-byte checks,
    /// as long as none comes after the inter-byte timeout. The servos see the same bytes at the
    /// same times either way (a property test pins the parser's side of this).
    fn hear(&mut self, heard: Heard, stop_at_reply: bool) -> bool {
        while let Some(&(at, byte)) = self.to_servos.front() {
            if !heard.holds(at) {
                break;
            }
            self.to_servos.pop_front();
            self.now_ns = at;
            let queued = self.to_master.len();
            self.servo_hears(at, byte);
            if stop_at_reply && self.to_master.len() != queued {
                return true;
            }
            for _ in 0..self.servo_parser.quiet_bytes() {
                match self.to_servos.front() {
                    Some(&(at, byte))
                        if heard.holds(at)
                            && at.saturating_sub(self.last_servo_byte_ns)
                                <= INTER_BYTE_TIMEOUT_NS =>
                    {
                        self.to_servos.pop_front();
                        self.now_ns = at;
                        self.last_servo_byte_ns = at;
                        self.servo_parser.push(byte);
                    }
                    _ => break,
                }
            }
        }
        false
    }

    fn servo_hears(&mut self, at: u64, byte: u8) {
        if at.saturating_sub(self.last_servo_byte_ns) > INTER_BYTE_TIMEOUT_NS {
            self.servo_parser.reset();
        }
        self.last_servo_byte_ns = at;
        self.servo_parser.push(byte);
        // Inside a packet whose last byte is still to come nothing can complete: the parser is
        // not asked (it was asked at every byte, a tenth of the simulated bus's time).
        if self.servo_parser.awaiting_rest() {
            return;
        }
        let baud = self.config.baud;
        // Borrow dance: the parser's frame borrows `self.servo_parser`, the chain is separate.
        let mut planned = Vec::new();
        while let Some(ev) = self.servo_parser.next_frame() {
            if let Ok(frame) = ev {
                if frame.instruction == crate::instruction::STATUS {
                    continue;
                }
                if at > self.physics_ns {
                    self.chain.step((at - self.physics_ns) as f64 * 1e-9);
                    self.physics_ns = at;
                }
                planned.extend(self.chain.handle(&frame, baud));
            }
        }
        let byte_ns = self.byte_ns();
        let mut prev_end = at;
        // Echo and replies may interleave: `queue_to_master` keeps the master's queue in time
        // order, sorting only when they do.
        for r in planned {
            let base = if r.chained {
                prev_end.max(self.reply_end_ns).max(at)
            } else {
                at
            };
            let start = base + r.delay_us as u64 * 1_000;
            if let Some(bytes) = r.bytes {
                self.queue_to_master(start, byte_ns, &bytes);
                prev_end = start + bytes.len() as u64 * byte_ns;
                self.reply_end_ns = prev_end;
                self.bytes_to_master += bytes.len() as u64;
            }
        }
    }
}

impl embedded_io_async::ErrorType for SimWire {
    type Error = SimIoError;
}

impl embedded_io_async::Read for SimWire {
    async fn read(&mut self, buf: &mut [u8]) -> Result<usize, Self::Error> {
        if buf.is_empty() {
            return Ok(0);
        }
        core::future::poll_fn(|_| {
            let mut s = self.state.borrow_mut();
            let now = s.now_ns;
            // The bytes due, in time order (the queue is kept sorted), copied from the queue's
            // two slices and then dropped from its front (draining element by element was
            // most of a read's time).
            let n = s.to_master.partition_point(|b| b.0 <= now).min(buf.len());
            let (front, back) = s.to_master.as_slices();
            let k = n.min(front.len());
            for (slot, b) in buf.iter_mut().zip(front[..k].iter().chain(&back[..n - k])) {
                *slot = b.1;
            }
            s.to_master.drain(..n);
            if n > 0 {
                Poll::Ready(Ok(n))
            } else {
                Poll::Pending
            }
        })
        .await
    }
}

impl embedded_io_async::ReadReady for SimWire {
    fn read_ready(&mut self) -> Result<bool, Self::Error> {
        let s = self.state.borrow();
        Ok(s.to_master.front().is_some_and(|b| b.0 <= s.now_ns))
    }
}

impl embedded_io_async::Write for SimWire {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, Self::Error> {
        let mut s = self.state.borrow_mut();
        let byte_ns = s.byte_ns();
        let start = s.master_tx_end_ns.max(s.now_ns);
        s.to_servos.extend(
            buf.iter()
                .enumerate()
                .map(|(i, &b)| (start + (i as u64 + 1) * byte_ns, b)),
        );
        s.master_tx_end_ns = start + buf.len() as u64 * byte_ns;
        s.bytes_to_servos += buf.len() as u64;
        if s.config.echo {
            s.queue_to_master(start, byte_ns, buf);
        }
        Ok(buf.len())
    }

    async fn flush(&mut self) -> Result<(), Self::Error> {
        let end = self.state.borrow().master_tx_end_ns;
        self.wait_until(end.div_ceil(1_000)).await;
        Ok(())
    }
}

impl Clock for SimWire {
    fn now_us(&self) -> u64 {
        SimWire::now_us(self)
    }

    async fn wait_until(&self, deadline_us: u64) {
        let deadline_ns = deadline_us * 1_000;
        core::future::poll_fn(|_| {
            let mut s = self.state.borrow_mut();
            if s.now_ns >= deadline_ns {
                return Poll::Ready(());
            }
            s.timer_ns = Some(s.timer_ns.map_or(deadline_ns, |t| t.min(deadline_ns)));
            Poll::Pending
        })
        .await
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The burst end kept across queued bytes is the one found afresh: bursts queued in order
    /// (continuing the last, after a gap, at the same time as the last byte) and out of order
    /// (sorted, then found again), as the clock moves on and the master reads.
    #[test]
    fn the_kept_burst_end_is_the_one_found_afresh() {
        let chain = VirtualChain::drosophibot(2, 1_000_000).expect("chain");
        let wire = SimWire::new(
            chain,
            WireConfig {
                baud: 1_000_000,
                echo: false,
            },
        );
        let mut s = wire.state.borrow_mut();
        let byte_ns = s.byte_ns();
        let mut seed = 0x2545_F491_4F6C_DD1Du64;
        let mut next = |n: u64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed % n
        };
        let mut checked = 0;
        for _ in 0..2000 {
            let now = s.now_ns;
            // Cache as block_on does it.
            if !matches!(s.burst_end_ns, Some(e) if e > now) {
                s.burst_end_ns = s.burst_end(now);
            }
            let back = s.to_master.back().map_or(now, |b| b.0);
            let start = match next(5) {
                0 => back,                                   // continues the last byte
                1 => back.saturating_sub(byte_ns),           // same time as the last byte
                2 => back + byte_ns * (1 + next(40)),        // after a gap
                3 => now.saturating_sub(next(20) * byte_ns), // maybe before queued bytes
                _ => now + next(30) * byte_ns,
            };
            let bytes = vec![0xA5; next(30) as usize];
            s.queue_to_master(start, byte_ns, &bytes);
            if let Some(end) = s.burst_end_ns
                && end > now
            {
                assert_eq!(Some(end), s.burst_end(now), "after queueing at {start}");
                checked += 1;
            }
            // Time moves on and the master reads what is due.
            s.now_ns += next(60) * byte_ns;
            let due = s.to_master.partition_point(|b| b.0 <= s.now_ns);
            let take = due.min(next(40) as usize);
            s.to_master.drain(..take);
        }
        assert!(checked > 300, "only {checked} kept ends were compared");
    }
}

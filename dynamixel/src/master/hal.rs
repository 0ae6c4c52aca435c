//! The two seams the bus master needs besides the UART: the transceiver's direction pin and a
//! clock with deadlines. The RP2040 implements them on embassy-rp/embassy-time, host tests on the
//! simulated wire ([`crate::sim`]), the U2D2 client on `std` time.

use core::future::Future;
use core::pin::pin;
use core::task::Poll;

/// The direction of a half-duplex transceiver (tri-state buffer or RS-485 style).
// Single-threaded executors drive these futures: no `Send` bound wanted.
#[allow(async_fn_in_trait)]
pub trait DirectionPin {
    /// Switches the transceiver to transmit; called before the first byte is written.
    fn drive(&mut self);
    /// Called after the packet was written and flushed: waits until the last stop bit has left
    /// the shift register (on the RP2040: poll the UART BUSY flag, since `flush` returns when the
    /// FIFO has taken the bytes), then switches back to receive.
    async fn release_after_tx(&mut self);
}

/// For adapters that switch direction themselves (U2D2) or full-duplex wiring.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct AutoDirection;

impl DirectionPin for AutoDirection {
    fn drive(&mut self) {}
    async fn release_after_tx(&mut self) {}
}

/// Monotonic microsecond time with deadlines.
#[allow(async_fn_in_trait)]
pub trait Clock {
    /// Microseconds since an arbitrary, fixed epoch.
    fn now_us(&self) -> u64;
    /// Resolves once `now_us() >= deadline_us`.
    async fn wait_until(&self, deadline_us: u64);
}

impl<C: Clock> Clock for &C {
    fn now_us(&self) -> u64 {
        (**self).now_us()
    }
    async fn wait_until(&self, deadline_us: u64) {
        (**self).wait_until(deadline_us).await
    }
}

/// Runs `fut` until it completes (`Some`) or the clock reaches `deadline_us` (`None`).
/// The future is polled first, so data that is already there wins over an expired deadline.
pub async fn with_deadline<C: Clock, F: Future>(clock: &C, deadline_us: u64, fut: F) -> Option<F::Output> {
    let mut fut = pin!(fut);
    let mut timer = pin!(clock.wait_until(deadline_us));
    core::future::poll_fn(|cx| {
        if let Poll::Ready(v) = fut.as_mut().poll(cx) {
            return Poll::Ready(Some(v));
        }
        if timer.as_mut().poll(cx).is_ready() {
            return Poll::Ready(None);
        }
        Poll::Pending
    })
    .await
}

//! A clock for tests that need no wall time: every wait ends at once, moving time to its deadline.

use std::cell::Cell;

use dynamixel::master::Clock;

/// Microseconds since it was made; `wait_until` jumps there instead of waiting.
#[derive(Debug, Default)]
pub struct JumpClock(Cell<u64>);

impl Clock for JumpClock {
    fn now_us(&self) -> u64 {
        self.0.get()
    }
    async fn wait_until(&self, deadline_us: u64) {
        self.0.set(self.0.get().max(deadline_us));
    }
}

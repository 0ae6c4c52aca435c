//! The bus master's reply schedule on the simulated wire: noise in a Sync Read's reply window, a
//! silent servo, a false header, and a window where every reply is garbled each cost only the
//! replies they hit, and the read ends by the schedule's deadline (issue #9, docs/reliability.md,
//! bus noise). Expected times are hand calculations at 1 Mbit/s (10 us a byte): a status packet
//! with 10 data bytes is 21 bytes = 210 us; the request of a cycle is 124 + 36 bytes = 1600 us.
#![cfg(feature = "std")]

use dynamixel::master::{
    AutoDirection, BusMaster, CycleStats, Goal, MasterConfig, Reply, ReplyFault,
};
use dynamixel::sim::{Faults, SimIoError, SimWire};
use embedded_io_async::{ErrorType, Read, ReadReady, Write};

/// The slack the firmware's simulated board uses (Return Delay Time 0): one reply's budget is
/// 210 + 100 = 310 us, shorter than two replies (420 us), as on the robot with its turnaround.
const SLACK_US: u32 = 100;
const REPLY_US: u64 = 210;
const BUDGET_US: u64 = REPLY_US + SLACK_US as u64;

/// The simulated wire with noise that starts at the first read after a request was sent: the
/// moment the master turns to listening, i.e. the start of the reply window. `SimWire` puts
/// the noise bytes between the reply bytes that arrive at the same time, which garbles both.
#[derive(Debug, Clone)]
struct NoisyWire {
    wire: SimWire,
    noise: Vec<u8>,
    armed: bool,
}

impl ErrorType for NoisyWire {
    type Error = SimIoError;
}

impl Read for NoisyWire {
    async fn read(&mut self, buf: &mut [u8]) -> Result<usize, Self::Error> {
        if self.armed {
            self.armed = false;
            self.wire.inject_noise(&std::mem::take(&mut self.noise));
        }
        self.wire.read(buf).await
    }
}

impl ReadReady for NoisyWire {
    fn read_ready(&mut self) -> Result<bool, Self::Error> {
        self.wire.read_ready()
    }
}

impl Write for NoisyWire {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, Self::Error> {
        self.armed = !self.noise.is_empty();
        self.wire.write(buf).await
    }

    async fn flush(&mut self) -> Result<(), Self::Error> {
        self.wire.flush().await
    }
}

type Master = BusMaster<NoisyWire, AutoDirection, SimWire>;

/// `n` servos at 1 Mbit/s, Return Delay Time 0, echo on; `noise` goes on the wire at the start of
/// the first reply window.
fn bus(n: u8, noise: Vec<u8>) -> (SimWire, Master) {
    let wire = SimWire::drosophibot(n, 1_000_000, 0).unwrap();
    let io = NoisyWire {
        wire: wire.clone(),
        noise,
        armed: false,
    };
    let config = MasterConfig {
        baud: 1_000_000,
        reply_slack_us: SLACK_US,
    };
    (
        wire.clone(),
        BusMaster::new(io, AutoDirection, wire, config),
    )
}

fn cycle(wire: &SimWire, m: &mut Master, n: u8) -> (Vec<Reply>, CycleStats) {
    let goals: Vec<Goal> = (1..=n).map(|id| Goal { id, position: 2048 }).collect();
    let mut replies = vec![Ok(Default::default()); goals.len()];
    let stats = wire.block_on(m.cycle(&goals, &mut replies)).unwrap();
    (replies, stats)
}

/// One cycle of 22 servos on a clean wire where servo `id` never answers.
fn cycle_with_silent(id: u8) -> (Vec<Reply>, CycleStats) {
    let (wire, mut m) = bus(22, Vec::new());
    wire.with_chain(|c| c.set_faults(id, Faults::SILENT))
        .unwrap();
    cycle(&wire, &mut m, 22)
}

fn lost(stats: &CycleStats) -> u8 {
    stats.timeouts + stats.crc_errors + stats.malformed
}

#[test]
fn noise_at_the_start_of_the_reply_window_costs_only_the_first_reply() {
    // 5 bytes of noise between servo 1's first 5 bytes: its header is gone.
    let (wire, mut m) = bus(22, vec![0x00; 5]);
    let (replies, stats) = cycle(&wire, &mut m, 22);
    assert!(replies[0].is_err(), "servo 1 was garbled: {:?}", replies[0]);
    assert!(
        replies[1..].iter().all(|r| r.is_ok()),
        "servos 2..=22: {replies:?}"
    );
    assert_eq!((stats.ok, lost(&stats)), (21, 1));
    // The read ends with servo 22's reply: 22 replies of 210 us after the request (the noise
    // came between servo 1's bytes and took no extra wire time in this model).
    assert_eq!(stats.end_us - stats.tx_end_us, 22 * REPLY_US);
    // The next cycle is clean: nothing of the burst is left over.
    let (replies, stats) = cycle(&wire, &mut m, 22);
    assert!(replies.iter().all(|r| r.is_ok()), "{replies:?}");
    assert_eq!(stats.stale_bytes, 0);
}

#[test]
fn a_silent_servo_in_the_middle_costs_only_itself() {
    let (replies, stats) = cycle_with_silent(11);
    assert_eq!(replies[10], Err(ReplyFault::Timeout));
    assert_eq!((stats.ok, stats.timeouts), (21, 1));
    // Servo 12 follows servo 10 directly (a silent servo takes no time on the simulated wire),
    // and the read ends with servo 22: 21 replies.
    assert_eq!(stats.end_us - stats.tx_end_us, 21 * REPLY_US);
}

#[test]
fn a_silent_last_servo_costs_one_reply_budget_as_before() {
    let (_, stats) = cycle_with_silent(22);
    assert_eq!((stats.ok, stats.timeouts), (21, 1));
    // After servo 21 the line stays quiet for one budget (its wire time plus the slack).
    assert_eq!(stats.end_us - stats.tx_end_us, 21 * REPLY_US + BUDGET_US);
}

#[test]
fn when_every_reply_is_garbled_the_read_ends_at_the_schedules_deadline() {
    // Noise for 30 ms (longer than the whole window): every reply has noise between its bytes.
    let (wire, mut m) = bus(22, vec![0x00; 3_000]);
    let (replies, stats) = cycle(&wire, &mut m, 22);
    assert!(replies.iter().all(|r| r.is_err()), "{replies:?}");
    assert_eq!(lost(&stats), 22);
    // The line never goes quiet, so the schedule ends the read: 22 slots of one budget each
    // after the request, the worst case of a read whose every reply comes at the last moment.
    assert_eq!(stats.end_us - stats.tx_end_us, 22 * BUDGET_US);
}

#[test]
fn when_every_servo_sends_a_bad_crc_each_is_counted_and_the_read_ends_with_the_last() {
    let (wire, mut m) = bus(22, Vec::new());
    let corrupt = Faults::BAD_CRC;
    wire.with_chain(|c| (1..=22).try_for_each(|id| c.set_faults(id, corrupt)))
        .unwrap();
    let (replies, stats) = cycle(&wire, &mut m, 22);
    assert!(replies.iter().all(|r| *r == Err(ReplyFault::Crc)));
    assert_eq!(stats.crc_errors, 22);
    // A bad packet under the ID due next is that servo's reply: the schedule moves on with it.
    assert_eq!(stats.end_us - stats.tx_end_us, 22 * REPLY_US);
}

#[test]
fn a_false_header_swallowing_the_replies_is_abandoned_when_its_slot_is_over() {
    // A false status header of servo 5 claiming 200 bytes (LEN 0x00C8) ahead of servo 1's reply,
    // which comes 200 us late (Return Delay Time 100 x 2 us) so that the header is whole.
    let header = vec![0xFF, 0xFF, 0xFD, 0x00, 0x05, 0xC8, 0x00];
    let (wire, mut m) = bus(3, header);
    wire.with_chain(|c| {
        c.servo_mut(1)
            .unwrap()
            .put(dynamixel::control_table::RETURN_DELAY_TIME, 100)
    });
    let (replies, stats) = cycle(&wire, &mut m, 3);
    assert!(replies.iter().all(|r| r.is_ok()), "{replies:?}");
    // The three replies (63 bytes) never fill the 207 bytes the header claims. At the end of
    // slot 1 (request end + 2 budgets) the parser holds more than any reply can be: the header
    // is dropped (7 garbage bytes) and replies 1 and 2 are found; the read ends with reply 3.
    assert_eq!(stats.garbage_bytes, 7);
    assert_eq!(stats.end_us - stats.tx_end_us, 200 + 3 * REPLY_US);
}

//! The fault knobs of the virtual servos as the bus master sees them on the simulated wire.

use super::{Faults, SimMaster, SimWire};
use crate::master::{Goal, MasterConfig, Reply, ReplyFault};

fn bus() -> (SimWire, SimMaster) {
    let wire = SimWire::drosophibot(6, 1_000_000, 0).unwrap();
    let m = wire.master(MasterConfig::new(1_000_000));
    (wire, m)
}

fn cycle(wire: &SimWire, m: &mut SimMaster) -> Vec<Reply> {
    let goals: Vec<Goal> = (1..=6).map(|id| Goal { id, position: 2048 }).collect();
    let mut replies = vec![Err(ReplyFault::Timeout); 6];
    wire.block_on(m.cycle(&goals, &mut replies)).unwrap();
    replies
}

#[test]
fn corrupt_next_spoils_exactly_that_many_replies_of_that_servo() {
    let (wire, mut m) = bus();
    wire.with_chain(|c| c.set_faults(5, Faults::corrupting_next(2)))
        .unwrap();
    for k in 0..4 {
        let replies = cycle(&wire, &mut m);
        for (i, r) in replies.iter().enumerate() {
            let want_crc_error = i == 4 && k < 2;
            assert_eq!(
                matches!(r, Err(ReplyFault::Crc)),
                want_crc_error,
                "cycle {k} servo {}: {r:?}",
                i + 1
            );
            if !want_crc_error {
                assert!(matches!(r, Ok(f) if f.position == 2048), "{r:?}");
            }
        }
    }
    wire.with_chain(|c| assert_eq!(c.servo(5).unwrap().faults.corrupt_next, 0));
}

#[test]
fn a_silent_servo_uses_up_no_corruption_and_a_stuck_one_answers_but_stays() {
    let (wire, mut m) = bus();
    wire.with_chain(|c| {
        c.set_faults(
            2,
            Faults {
                corrupt_next: 1,
                ..Faults::SILENT
            },
        )
        .unwrap();
        c.set_faults(3, Faults::JAMMED).unwrap();
    });
    // Torque on, then goals 300 ticks away for 0.5 s: the others get there, servo 3 does not.
    wire.with_chain(|c| {
        for s in c.servos_mut() {
            s.put(crate::control_table::TORQUE_ENABLE, 1);
        }
    });
    let goals: Vec<Goal> = (1..=6).map(|id| Goal { id, position: 2348 }).collect();
    let mut replies = vec![Err(ReplyFault::Timeout); 6];
    for _ in 0..50 {
        wire.block_on(m.cycle(&goals, &mut replies)).unwrap();
        wire.advance_us(10_000 - 1);
    }
    assert_eq!(replies[1], Err(ReplyFault::Timeout));
    assert!(
        matches!(replies[2], Ok(f) if f.position == 2048 && !f.alert),
        "{:?}",
        replies[2]
    );
    for i in [0, 3, 4, 5] {
        assert!(
            matches!(replies[i], Ok(f) if (f.position - 2348).abs() <= 1),
            "{:?}",
            replies[i]
        );
    }
    // Back on the bus, servo 2's one corrupt reply is still to come.
    wire.with_chain(|c| c.set_faults(2, Faults::corrupting_next(1)))
        .unwrap();
    assert_eq!(cycle(&wire, &mut m)[1], Err(ReplyFault::Crc));
}

#[test]
fn an_external_plant_sets_what_the_servo_reports_and_its_own_motor_stays_still() {
    use crate::control_table as ct;
    let mut s = super::VirtualServo::new(1, crate::ServoModel::Mx28, 3, 1000);
    s.external_plant = true;
    s.put(ct::TORQUE_ENABLE, 1);
    s.put(ct::GOAL_POSITION, 3000);
    s.step(1.0);
    assert_eq!(
        s.get(ct::PRESENT_POSITION),
        1000,
        "its own motor model must not run"
    );
    // 2048.4 ticks, 10 velocity units of 0.229 rpm, 1.25 N m = half the MX-28's 2.5 N m stall
    // torque: load 500 (0.1 % units).
    let tick = crate::units::RAD_PER_TICK as f64;
    let unit = crate::units::RAD_S_PER_VELOCITY_UNIT as f64;
    s.set_motor_state(crate::sim::physics::MotorState {
        angle_rad: 2048.4 * tick,
        velocity_rad_s: -10.0 * unit,
        torque_nm: 1.25,
        duty: 0.5,
    });
    assert_eq!(s.get(ct::PRESENT_POSITION), 2048);
    assert_eq!(s.get(ct::PRESENT_VELOCITY) as i32, -10);
    assert_eq!(s.get(ct::PRESENT_LOAD_OR_CURRENT) as u16 as i16, 500);
}

/// Counts how often the executor polls the future it wraps.
struct CountPolls<'a, F> {
    inner: core::pin::Pin<&'a mut F>,
    polls: &'a core::cell::Cell<u32>,
}

impl<F: core::future::Future> core::future::Future for CountPolls<'_, F> {
    type Output = F::Output;
    fn poll(
        mut self: core::pin::Pin<&mut Self>,
        cx: &mut core::task::Context<'_>,
    ) -> core::task::Poll<F::Output> {
        self.polls.set(self.polls.get() + 1);
        self.inner.as_mut().poll(cx)
    }
}

#[test]
fn echoed_bytes_wake_the_master_once_per_burst_not_once_per_byte() {
    let (wire, mut m) = bus();
    let goals: Vec<Goal> = (1..=6).map(|id| Goal { id, position: 2048 }).collect();
    let mut replies = vec![Err(ReplyFault::Timeout); 6];
    let polls = core::cell::Cell::new(0);
    let (sent_before, _) = wire.byte_counts();
    {
        let fut = core::pin::pin!(m.cycle(&goals, &mut replies));
        wire.block_on(CountPolls {
            inner: fut,
            polls: &polls,
        })
        .unwrap();
    }
    let sent = wire.byte_counts().0 - sent_before;
    for r in &replies {
        assert!(matches!(r, Ok(f) if f.position == 2048), "{r:?}");
    }
    // Each byte the master sends comes back as its echo at the moment the servos hear it. Before,
    // every one of them woke the master's future; now a request's echo is one burst (one wake at
    // its last byte) and each reply one more, so a cycle wakes a handful of times per packet
    // (measured: 4 polls for this cycle's 64 bytes; 67 with a wake per echoed byte).
    assert!(sent > 60, "the cycle's requests are {sent} bytes");
    assert!(
        u64::from(polls.get()) * 4 < sent,
        "{} polls for {sent} bytes sent: one wake per echoed byte",
        polls.get()
    );
}

/// An empty noise burst or write queues nothing toward the master (the soak's bursts are 0 to 47
/// bytes): the wire takes it, on an empty queue too, and the next cycle is answered in full.
#[test]
fn an_empty_noise_burst_or_write_changes_nothing() {
    use embedded_io_async::Write;
    let (wire, mut m) = bus();
    wire.inject_noise(&[]);
    let mut w = wire.clone();
    assert_eq!(wire.block_on(w.write(&[])), Ok(0));
    for r in cycle(&wire, &mut m) {
        assert!(matches!(r, Ok(f) if f.position == 2048), "{r:?}");
    }
    wire.inject_noise(&[]);
    for r in cycle(&wire, &mut m) {
        assert!(matches!(r, Ok(f) if f.position == 2048), "{r:?}");
    }
}

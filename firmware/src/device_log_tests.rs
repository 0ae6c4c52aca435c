//! The device log's hook is called at every state change and fault: the whole firmware (link,
//! controller, bus loop) on the simulated wire with 22 virtual servos is taken through boot, an
//! upload, a walk, a servo overload, a second fault, an emergency stop and a clear, and the trail
//! of logged lines is compared with the path through the state diagram of `safety/mod.rs`, worked
//! out by hand. After every bus cycle and every command the last logged state must be the
//! controller's state, so no change can go unlogged.

use dynamixel::sim::SimWire;
use protocol::{Client, Request, Response};

use super::Cause;
use super::trail::{self, Entry};
use crate::safety::{Event, SafeReason, State};
use crate::testkit::SyntheticGait;
use crate::testkit::rig::{SimBoard, ask, play, rig, upload};

/// Hardware Error Status bit 5: overload (e-manual, MX(2.0) address 70).
const OVERLOAD: u8 = 1 << 5;

/// A board on the simulated wire with the trail of everything it logged so far.
struct Rig {
    board: SimBoard,
    wire: SimWire,
    client: Client,
    logged: Vec<Entry>,
}

impl Rig {
    fn new() -> Self {
        let (board, wire) = rig(1_000_000, 100);
        trail::take();
        Self {
            board,
            wire,
            client: Client::new(),
            logged: Vec::new(),
        }
    }

    fn state(&self) -> State {
        self.board.controller.borrow().state()
    }

    /// Takes what was logged since the last check and asserts the trail ends in the present state.
    fn check(&mut self, after: &str) {
        self.logged.extend(trail::take());
        let last = self.logged.last().map_or(State::Boot, |e| e.to);
        assert_eq!(
            last,
            self.state(),
            "after {after}: the controller is in {:?} but the log last said {last:?}",
            self.state()
        );
    }

    fn cycles_until(&mut self, max: usize, done: impl Fn(State) -> bool) {
        for _ in 0..max {
            if done(self.state()) {
                return;
            }
            self.cycles(1);
        }
        panic!("not done after {max} cycles: {:?}", self.state());
    }

    /// `n` bus cycles, whatever the state.
    fn cycles(&mut self, n: usize) {
        for i in 0..n {
            self.wire.block_on(self.board.run_cycle());
            self.board.drain_telemetry(|_| {});
            self.check(&format!("bus cycle {i} of {n}"));
        }
    }

    fn ask(&mut self, request: Request) -> Response {
        let what = format!("{request:?}");
        let r = ask(&mut self.board, &mut self.client, request);
        self.check(&what);
        r
    }
}

#[test]
fn every_state_change_and_fault_is_logged_where_it_happens() {
    let mut r = Rig::new();
    // Empty store: no joint map, so Boot is done at the first cycle.
    r.cycles_until(5, |s| s == State::Idle);
    // The upload selects a gait with 22 servos: the controller looks for them.
    let gait = SyntheticGait::new(100, 1.0);
    upload(&mut r.board, &mut r.client, 0, &gait.build());
    r.check("the upload");
    r.cycles_until(5, |s| s == State::Idle);
    // One step, played to its end.
    play(&mut r.board, &mut r.client, protocol::Steps::Count(1));
    r.check("Play");
    r.cycles_until(1000, |s| s == State::Standing);
    // Walking again; servo ID 3 (joint 2) overloads: its Alert bit, then its error bits are read.
    play(&mut r.board, &mut r.client, protocol::Steps::Continuous);
    r.check("Play");
    r.cycles_until(1000, |s| s == State::Walking);
    r.wire.with_chain(|c| c.trigger_overload(3)).unwrap();
    r.cycles_until(
        10,
        |s| matches!(s, State::Safe(SafeReason::ServoError { error, .. }) if error != 0),
    );
    // A second servo overloads while Safe: logged, and the first fault stays the one reported.
    r.wire.with_chain(|c| c.trigger_overload(5)).unwrap();
    r.cycles(20);
    assert_eq!(r.ask(Request::EmergencyStop), Response::Ack);
    assert_eq!(r.ask(Request::ClearFault), Response::Ack);

    let fault = |error| {
        State::Safe(SafeReason::ServoError {
            joint: 2,
            id: 3,
            error,
        })
    };
    let first = SafeReason::ServoError {
        joint: 2,
        id: 3,
        error: 0,
    };
    let second = SafeReason::ServoError {
        joint: 4,
        id: 5,
        error: 0,
    };
    let ev = Cause::Event;
    let e = |from, to, cause| Entry { from, to, cause };
    let want = [
        e(State::Boot, State::Idle, ev(Event::BootDone)),
        e(State::Idle, State::Boot, Cause::NewJointMap),
        e(State::Boot, State::Idle, ev(Event::BootDone)),
        e(State::Idle, State::Ramping, ev(Event::Start)),
        e(State::Ramping, State::Walking, ev(Event::RampDone)),
        e(State::Walking, State::Standing, ev(Event::StepsDone)),
        e(State::Standing, State::Ramping, ev(Event::Start)),
        e(State::Ramping, State::Walking, ev(Event::RampDone)),
        e(State::Walking, fault(0), ev(Event::Fault(first))),
        e(fault(0), fault(OVERLOAD), Cause::ErrorBits),
        e(fault(OVERLOAD), fault(OVERLOAD), ev(Event::Fault(second))),
        e(fault(OVERLOAD), State::EStop, ev(Event::EStop)),
        e(State::EStop, State::Idle, ev(Event::ClearFault)),
    ];
    assert_eq!(r.logged, want, "logged trail");
}

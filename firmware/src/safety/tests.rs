//! Every state x event pair of the safety state machine against a table written out by hand.

use super::*;

const WD: SafeReason = SafeReason::Watchdog;
const HW: SafeReason = SafeReason::ServoError {
    joint: 3,
    id: 7,
    error: 0x20,
};

const STATES: [State; 9] = [
    State::Boot,
    State::Idle,
    State::Standing,
    State::Ramping,
    State::Walking,
    State::Stopping,
    State::Streaming,
    State::Safe(WD),
    State::EStop,
];

const EVENTS: [Event; 18] = [
    Event::BootDone,
    Event::TorqueOn,
    Event::TorqueOff,
    Event::Start,
    Event::RampDone,
    Event::Stop,
    Event::EndOfStep,
    Event::StepsDone,
    Event::EnterStreaming,
    Event::LeaveStreaming,
    Event::EStop,
    Event::Fault(HW),
    Event::ClearFault,
    Event::Reboot,
    Event::Queue,
    Event::ClearQueue,
    Event::Switch,
    Event::Steer,
];

#[test]
fn every_transition_matches_the_design_table() {
    use State::*;
    const X: Option<State> = None;
    const fn s(state: State) -> Option<State> {
        Some(state)
    }
    // Rows: states in STATES order; columns: events in EVENTS order. `X` = refused.
    #[rustfmt::skip]
    let table: [[Option<State>; 18]; 9] = [
        //           BootDone  TorqOn       TorqOff  Start       RampDone    Stop           EndOfStep    StepsDone      EnterStr       LeaveStr       EStop     Fault(HW)       Clear    Reboot     Queue        ClearQueue     Switch       Steer
        /*Boot*/    [s(Idle),  X,           X,       X,          X,          X,             X,           X,             X,             X,             s(EStop), s(Safe(HW)),    X,       X, X,           X,             X, X],
        /*Idle*/    [X,        s(Standing), s(Idle), s(Ramping), X,          s(Idle),       X,           X,             s(Streaming),  X,             s(EStop), s(Safe(HW)),    X,       s(Boot), X,           s(Idle),       X, X],
        /*Standing*/[X,        s(Standing), s(Idle), s(Ramping), X,          s(Standing),   X,           X,             s(Streaming),  X,             s(EStop), s(Safe(HW)),    X,       s(Boot), X,           s(Standing),   X, X],
        /*Ramping*/ [X,        X,           X,       X,          s(Walking), s(Standing),   X,           X,             X,             X,             s(EStop), s(Safe(HW)),    X,       X, s(Ramping), s(Ramping),    X, s(Ramping)],
        /*Walking*/ [X,        X,           X,       X,          X,          s(Stopping),   s(Walking),  s(Standing),   X,             X,             s(EStop), s(Safe(HW)),    X,       X, s(Walking), s(Walking),    s(Walking), s(Walking)],
        /*Stopping*/[X,        X,           X,       X,          X,          s(Stopping),   s(Standing), s(Standing),   X,             X,             s(EStop), s(Safe(HW)),    X,       X, X,           s(Stopping),   X, X],
        /*Streamin*/[X,        X,           X,       X,          X,          s(Standing),   X,           X,             X,             s(Standing),   s(EStop), s(Safe(HW)),    X,       X, X,           X,             X, X],
        /*Safe(WD)*/[X,        X,           X,       X,          X,          X,             X,           X,             X,             X,             s(EStop), s(Safe(WD)),    s(Idle), s(Boot), X,           X,             X, X],
        /*EStop*/   [X,        X,           X,       X,          X,          X,             X,           X,             X,             X,             s(EStop), s(EStop),       s(Idle), s(Boot), X,           X,             X, X],
    ];
    for (s, row) in STATES.iter().zip(table) {
        for (e, want) in EVENTS.iter().zip(row) {
            let got = s.next(*e);
            match want {
                Some(next) => assert_eq!(got, Ok(next), "{s:?} + {e:?}"),
                None => assert_eq!(
                    got,
                    Err(Refused {
                        state: *s,
                        event: *e
                    }),
                    "{s:?} + {e:?}"
                ),
            }
        }
    }
}

#[test]
fn goals_are_driven_only_while_torque_is_meant_to_be_on() {
    let drives: Vec<bool> = STATES.iter().map(|s| s.drives_goals()).collect();
    assert_eq!(
        drives,
        [false, false, true, true, true, true, true, false, false]
    );
    let plays: Vec<bool> = STATES.iter().map(|s| s.plays()).collect();
    assert_eq!(
        plays,
        [false, false, false, false, true, true, false, false, false]
    );
    let flash: Vec<bool> = STATES.iter().map(|s| s.allows_flash_writes()).collect();
    assert_eq!(
        flash,
        [true, true, true, false, false, false, false, true, true]
    );
}

#[test]
fn a_servo_is_missing_after_the_limit_of_consecutive_misses_only() {
    let mut m = MissCounter::<3>::new(3);
    assert_eq!(m.record(1, 12, false), None);
    assert_eq!(m.record(1, 12, false), None);
    // An answer in between resets the count.
    assert_eq!(m.record(1, 12, true), None);
    assert_eq!(m.record(1, 12, false), None);
    assert_eq!(m.record(1, 12, false), None);
    // Misses of another servo do not add up with this one's.
    assert_eq!(m.record(2, 13, false), None);
    assert_eq!(
        m.record(1, 12, false),
        Some(SafeReason::ServoMissing {
            joint: 1,
            id: 12,
            cycles: 3
        })
    );
    m.reset();
    assert_eq!(m.record(1, 12, false), None);
    // Out-of-range joint is ignored rather than panicking.
    assert_eq!(m.record(9, 1, false), None);
}

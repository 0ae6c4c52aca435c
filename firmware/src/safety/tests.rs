//! Every state x event pair of the safety state machine against a table written out by hand.

use super::*;

const WD: SafeReason = SafeReason::Watchdog;
const HW: SafeReason = SafeReason::ServoError { id: 7, error: 0x20 };

const STATES: [State; 7] = [
    State::Boot,
    State::Idle,
    State::Ramping,
    State::Walking,
    State::Stopping,
    State::Safe(WD),
    State::EStop,
];

const EVENTS: [Event; 9] = [
    Event::BootDone,
    Event::Start,
    Event::RampDone,
    Event::Stop,
    Event::EndOfStep,
    Event::StepsDone,
    Event::EStop,
    Event::Fault(HW),
    Event::Reboot,
];

#[test]
fn every_transition_matches_the_design_table() {
    use State::*;
    // Rows: states in STATES order; columns: events in EVENTS order. `None` = refused.
    let x: Option<State> = None;
    let table: [[Option<State>; 9]; 7] = [
        //        BootDone    Start          RampDone       Stop            EndOfStep      StepsDone   EStop        Fault(HW)           Reboot
        /*Boot*/ [Some(Idle), x, x, x, x, x, Some(EStop), Some(Safe(HW)), x],
        /*Idle*/ [x, Some(Ramping), x, Some(Idle), x, x, Some(EStop), Some(Safe(HW)), Some(Boot)],
        /*Ramp*/ [x, x, Some(Walking), Some(Idle), x, x, Some(EStop), Some(Safe(HW)), x],
        /*Walk*/ [x, x, x, Some(Stopping), Some(Walking), Some(Idle), Some(EStop), Some(Safe(HW)), x],
        /*Stop*/ [x, x, x, Some(Stopping), Some(Idle), Some(Idle), Some(EStop), Some(Safe(HW)), x],
        /*Safe*/ [x, x, x, x, x, x, Some(EStop), Some(Safe(WD)), Some(Boot)],
        /*EStp*/ [x, x, x, x, x, x, Some(EStop), Some(EStop), Some(Boot)],
    ];
    for (s, row) in STATES.iter().zip(table) {
        for (e, want) in EVENTS.iter().zip(row) {
            let got = s.next(*e);
            match want {
                Some(next) => assert_eq!(got, Ok(next), "{s:?} + {e:?}"),
                None => assert_eq!(got, Err(Refused { state: *s, event: *e }), "{s:?} + {e:?}"),
            }
        }
    }
}

#[test]
fn goals_are_driven_only_while_the_robot_is_meant_to_hold_or_move() {
    let drives: Vec<bool> = STATES.iter().map(|s| s.drives_goals()).collect();
    assert_eq!(drives, [false, true, true, true, true, false, false]);
    let plays: Vec<bool> = STATES.iter().map(|s| s.plays()).collect();
    assert_eq!(plays, [false, false, false, true, true, false, false]);
    let flash: Vec<bool> = STATES.iter().map(|s| s.allows_flash_writes()).collect();
    assert_eq!(flash, [true, true, false, false, false, true, true]);
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
        Some(SafeReason::ServoMissing { id: 12, cycles: 3 })
    );
    m.reset();
    assert_eq!(m.record(1, 12, false), None);
    // Out-of-range index is ignored rather than panicking.
    assert_eq!(m.record(9, 1, false), None);
}

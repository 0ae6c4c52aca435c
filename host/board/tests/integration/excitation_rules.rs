//! Excitation trials (planner::excitation) under the board's rules: every default table of
//! Drosophibot II is accepted as any gait is (slot size, servo feasibility, P gain), and an
//! excitation faster than the servos is refused in the rule's words, naming the joint.

use board::rules::RuleError;
use board::rules::build::excitation_table;
use planner::excitation::{ExcitationKind, ExcitationOptions, excitation};
use planner::model::builtin;

#[test]
fn the_default_excitations_pass_the_rules_of_any_gait() {
    let m = builtin("drosophibot2").unwrap();
    for kind in ExcitationKind::ALL {
        let e = excitation(&m, kind, &ExcitationOptions::default()).unwrap();
        for t in &e.trials {
            let table = excitation_table(&m, t).unwrap_or_else(|err| panic!("{}: {err}", t.name));
            assert!(table.warning().is_none(), "{}", t.name);
            let parsed = protocol::GaitTable::parse(table.bytes()).unwrap();
            assert_eq!(parsed.slice_count(), t.slices());
            // The period is the slices' time, to the table's microsecond.
            let period = f64::from(parsed.header().step_period_us) * 1e-6;
            assert!((period - t.period_s()).abs() < 1e-6, "{}", t.name);
            // Each fits a slot of the board with room to spare.
            assert!(
                t.slices() <= board::rules::slots::max_slices(22),
                "{}",
                t.name
            );
        }
    }
}

#[test]
fn an_excitation_faster_than_the_servos_is_refused() {
    // Steps at 1.5 times the no-load speed (MX-28: 1.5 x 5.76 = 8.6 rad/s, a 0.15 rad step in
    // 17 ms), sampled at 5 ms slices so that the rule's central differences see that speed:
    // over the e-manual's 5.76 rad/s, refused.
    let m = builtin("drosophibot2").unwrap();
    let options = ExcitationOptions {
        speed_fraction: 1.5,
        suspended_dt_s: 0.005,
        chirp_s: 4.0,
        hold_s: 0.3,
        ..ExcitationOptions::default()
    };
    let e = excitation(&m, ExcitationKind::Suspended, &options).unwrap();
    let t = e.trials.iter().find(|t| t.name == "sus-ThC1").unwrap();
    let err = excitation_table(&m, t).unwrap_err();
    assert!(matches!(err, RuleError::Infeasible { .. }), "{err}");
    let words = err.to_string();
    assert!(
        words.contains("excitation sus-ThC1 of drosophibot2") && words.contains("LF_ThC1"),
        "{words}"
    );
}

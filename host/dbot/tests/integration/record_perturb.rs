//! `dbot record --perturb LEG:STEP:MOVE` (issue 29 item 3): a leg that is not a leg, a step
//! beyond the run's steps, the lab's ID 22 given for the built-in model (a joint's servo), and a
//! platform servo that does not answer at the default ID 23 (the virtual robot has none) are refused with words before
//! anything moves, and no trial is kept; `dbot run --perturb` refuses alike.

use crate::board_fakes;
use std::path::Path;

use board::trial::list_trials;
use board_fakes::cli::{fails_naming, run, strings, table};

fn record(dir: &Path, perturb: &[&str]) -> board_fakes::cli::Done {
    let t = table(dir, "g.dbgt", 40, 0.4);
    let trials = dir.join("trials");
    let mut a = strings(&[
        "record",
        "--out",
        trials.to_str().unwrap(),
        "--table",
        &t,
        "--play",
        "0",
        "--steps",
        "2",
        "--port",
        "virtual",
        // 40 slices in 0.4 s: 6.26 rad/s, over the MX-28's 5.76 (the servo rule of a table file).
        "--allow-infeasible",
    ]);
    a.extend(strings(perturb));
    run(dir, &a)
}

fn no_trial(dir: &Path) {
    let trials = dir.join("trials");
    let kept = if trials.exists() {
        list_trials(&trials).unwrap().len()
    } else {
        0
    };
    assert_eq!(kept, 0, "a refused perturbation kept a trial");
}

#[test]
fn a_leg_that_is_not_a_leg_and_a_step_beyond_the_run_are_refused_before_the_port_opens() {
    let dir = tempfile::tempdir().unwrap();
    let d = record(dir.path(), &["--perturb", "LX:1:rise"]);
    fails_naming(
        &d,
        "--perturb LX",
        &["perturb LX:1:rise", "perturbation leg `LX` is not a leg"],
    );
    no_trial(dir.path());
    // Two steps are 0 and 1.
    let d = record(dir.path(), &["--perturb", "RM:2:rise"]);
    fails_naming(
        &d,
        "--perturb RM:2",
        &[
            "perturbation step 2 is beyond the run's 2 steps",
            "the last is 1",
        ],
    );
    no_trial(dir.path());
}

#[test]
fn a_joints_id_and_a_platform_servo_that_does_not_answer_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let d = record(
        dir.path(),
        &["--perturb", "RM:1:rise", "--platform-id", "22"],
    );
    fails_naming(
        &d,
        "the lab's ID 22",
        &["platform servo ID 22 is the ID of joint 21"],
    );
    no_trial(dir.path());
    let d = record(dir.path(), &["--perturb", "RM:1:fall"]);
    fails_naming(
        &d,
        "no servo at 23",
        &["virtual: perturbation platform: platform servo ID 23 does not answer"],
    );
    no_trial(dir.path());
}

#[test]
fn dbot_run_refuses_the_same_perturbations_in_the_same_words() {
    let dir = tempfile::tempdir().unwrap();
    let t = table(dir.path(), "g.dbgt", 40, 0.4);
    let run_with = |extra: &[&str]| {
        let mut a = strings(&[
            "run",
            "--table",
            &t,
            "--steps",
            "2",
            "--port",
            "virtual",
            "--allow-infeasible",
        ]);
        a.extend(strings(extra));
        run(dir.path(), &a)
    };
    let d = run_with(&["--perturb", "RM:2:rise"]);
    fails_naming(
        &d,
        "run --perturb RM:2",
        &[
            "perturb RM:2:rise",
            "perturbation step 2 is beyond the run's 2 steps",
        ],
    );
    let d = run_with(&["--perturb", "RM:1:rise", "--platform-id", "23"]);
    fails_naming(
        &d,
        "run: no servo at 23",
        &["virtual: perturbation platform: platform servo ID 23 does not answer"],
    );
    // Without --perturb the walk runs as before.
    let d = run_with(&[]);
    assert!(d.status.success(), "{}{}", d.stdout, d.stderr);
}

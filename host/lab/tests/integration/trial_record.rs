//! `lab::trial_record::record_trial` refuses, in the CLI's words, before anything moves: a trial
//! folder that exists, a perturbation step beyond the steps played, a leg that is not a leg, a
//! period shorter than planned at which the servos cannot follow the table (the words of `dbot run
//! --period`, `board::rules::period`). The virtual robot is still where it was (its state, its
//! counters) and no trial folder appears.

use lab::trial_record::{TrialHooks, TrialPlay, TrialRequest, record_trial};

/// Hooks that never stop and keep what was said.
#[derive(Default)]
struct Quiet {
    said: Vec<String>,
}

impl TrialHooks for Quiet {
    fn should_stop(&mut self) -> bool {
        false
    }
    fn say(&mut self, line: &str) {
        self.said.push(line.to_owned());
    }
}

fn request(out: &std::path::Path) -> TrialRequest {
    TrialRequest {
        command_line: vec!["test".to_owned()],
        ..TrialRequest::playing(
            out,
            0,
            Some(2),
            planner::model::builtin("drosophibot2").unwrap(),
        )
    }
}

#[test]
fn refusals_come_before_anything_moves() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("trials");
    std::fs::create_dir_all(out.join("mine")).unwrap();
    let mut board = physics::open("virtual").unwrap();
    let before = board.status().unwrap();

    let exists = TrialRequest {
        trial: Some("mine".to_owned()),
        ..request(&out)
    };
    let beyond = TrialRequest {
        perturb: Some("RM:2:rise".to_owned()),
        ..request(&out)
    };
    let no_leg = TrialRequest {
        perturb: Some("XY:1:rise".to_owned()),
        ..request(&out)
    };
    for (req, words) in [
        (exists, "mine exists: a trial never reuses a folder"),
        (
            beyond,
            "perturb RM:2:rise: perturbation platform: perturbation step 2 is beyond the run's 2 steps",
        ),
        (
            no_leg,
            "perturb XY:1:rise: perturbation leg `XY` is not a leg (legs: LF, LM, LH, RF, RM, RH)",
        ),
    ] {
        let mut hooks = Quiet::default();
        let e = record_trial(&mut board, &req, &mut hooks).unwrap_err();
        let text = e.chain_text();
        assert!(text.contains(words), "{text}");
        // Nothing said: no upload, no announcement, no walk.
        assert!(hooks.said.is_empty(), "{:?}", hooks.said);
    }
    let after = board.status().unwrap();
    assert_eq!(after.state, before.state);
    assert_eq!(after.counters, before.counters);
    // Only the folder that was there: no trial, no partial folder left.
    let names: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n != "TRIAL INDEX.txt")
        .collect();
    assert_eq!(names, ["mine"]);
}

/// The folders in `out`, trials and partial ones (none if `out` was never made).
fn trials_in(out: &std::path::Path) -> Vec<String> {
    match std::fs::read_dir(out) {
        Ok(entries) => entries
            .map(|e| e.unwrap())
            .filter(|e| e.file_type().unwrap().is_dir())
            .map(|e| e.file_name().into_string().unwrap())
            .collect(),
        Err(_) => Vec::new(),
    }
}

#[test]
fn a_period_the_servos_cannot_follow_is_refused_in_the_words_of_run() {
    // The paper's table 1 (0.5 s swing, 1.25 s per step): its front FTi servos already turn
    // faster than the MX-28's no-load speed as planned, so faster still is refused.
    let model = planner::model::builtin("drosophibot2").unwrap();
    let plan =
        planner::plan::plan(&model, &planner::gait::StepParams::table1(&model.name)).unwrap();
    // LF_FTi's peak speed by central differences (the paper's equation 1) against the MX-28's
    // 55 rev/min no-load speed (e-manual) at 0.9 times the period.
    let j = plan
        .model
        .joints
        .iter()
        .position(|j| j.name == "LF_FTi")
        .unwrap();
    let n = plan.q.len();
    let peak = (0..n)
        .map(|s| (plan.q[(s + 1) % n][j] - plan.q[(s + n - 1) % n][j]).abs() / (2.0 * plan.dt))
        .fold(0.0, f64::max);
    let no_load = 55.0 * std::f64::consts::TAU / 60.0;
    assert!(peak / 0.9 > no_load, "{peak} rad/s");
    let bytes = planner::plan::table::step_table(&plan, None, "fast").unwrap();
    let planned = f64::from(
        protocol::GaitTable::parse(&bytes)
            .unwrap()
            .header()
            .step_period_us,
    ) * 1e-6;
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("trials");
    let mut board = physics::open("virtual").unwrap();
    gate::upload(&mut board, 0, &bytes).unwrap();
    let fast = |allow_infeasible: bool, held: bool| TrialRequest {
        play: Some(TrialPlay {
            slot: 0,
            steps: Some(1),
            backward: false,
            period: Some(0.9 * planned),
            allow_infeasible,
        }),
        held_table: held.then(|| bytes.clone()),
        ..request(&out)
    };
    // What `dbot run --period` and `Board.play` are refused with: the rule on the same command.
    let by_run = board::rules::period::check_play(
        &mut board,
        protocol::PlayCommand::new(
            0,
            protocol::Direction::Forward,
            900,
            protocol::Steps::Count(1),
        ),
        Some(&bytes),
        &model,
        board::rules::Overrides::default(),
    )
    .unwrap_err()
    .to_string();
    let before = board.status().unwrap();

    let mut hooks = Quiet::default();
    let e = record_trial(&mut board, &fast(false, true), &mut hooks).unwrap_err();
    assert_eq!(e.chain_text(), by_run);
    assert!(
        by_run.starts_with(&format!(
            "slot 0 (\"fast\"): at {:.3} s per step (0.900 times the planned {planned:.3} s) the servos cannot follow it:\n",
            0.9 * planned
        )),
        "{by_run}"
    );
    // A table the door does not hold (a board's, not uploaded by this host) cannot be checked.
    let e = record_trial(&mut board, &fast(false, false), &mut hooks).unwrap_err();
    assert!(
        e.chain_text().contains("this host does not hold its table"),
        "{}",
        e.chain_text()
    );
    assert!(hooks.said.is_empty(), "{:?}", hooks.said);
    let after = board.status().unwrap();
    assert_eq!(after.state, before.state);
    assert_eq!(after.counters, before.counters);
    assert!(trials_in(&out).is_empty(), "{:?}", trials_in(&out));

    // The override plays it, warning in the rule's words first.
    let summary = record_trial(&mut board, &fast(true, true), &mut hooks).unwrap();
    assert!(
        hooks.said[0].starts_with("warning: slot 0 (\"fast\"): the servos cannot follow this plan"),
        "{:?}",
        hooks.said
    );
    assert_eq!(trials_in(&out).len(), 1, "{summary}: {:?}", trials_in(&out));
}

/// A servo that jams during a recorded walk (issue 43 item 3): the board stops the robot on
/// `ServoStuck`, and the trial ends as faulted, not complete: the rows up to the first record in
/// the fault state kept, the fault's kind, words, joint and cycle in trial.json and the README,
/// the folder named `... faulted`, and `record_trial` fails with `LabError::Faulted` naming them.
#[test]
fn a_fault_during_the_recording_ends_the_trial_as_faulted() {
    let model = planner::model::builtin("drosophibot2").unwrap();
    let params = planner::gait::StepParams::preset("servo-safe", &model.name).unwrap();
    let plan = planner::plan::plan(&model, &params).unwrap();
    let bytes = planner::plan::table::step_table(&plan, None, "safe").unwrap();
    let table = protocol::GaitTable::parse(&bytes).unwrap();
    // The joint that swings most over the step: the stuck rule sees its goal move.
    let swing = |j: usize| {
        let a: Vec<i16> = (0..table.slice_count())
            .map(|s| table.angle(s, j).unwrap())
            .collect();
        i32::from(*a.iter().max().unwrap()) - i32::from(*a.iter().min().unwrap())
    };
    let joint = (0..table.joint_count()).max_by_key(|&j| swing(j)).unwrap();
    let id = table.joint(joint).unwrap().servo_id;
    let name = board::record::joint_names(&model, Some(&table), table.joint_count())[joint].clone();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("trials");
    let mut board = physics::open("virtual").unwrap();
    gate::upload(&mut board, 0, &bytes).unwrap();
    let physics::RobotLink::Virtual(link) = board.transport() else {
        panic!("`virtual` opens the virtual robot")
    };
    link.robot()
        .with_chain(|c| {
            c.set_faults(
                id,
                dynamixel::sim::Faults {
                    stuck: true,
                    ..dynamixel::sim::Faults::NONE
                },
            )
        })
        .unwrap();
    let req = TrialRequest {
        play: Some(TrialPlay {
            slot: 0,
            steps: Some(4),
            backward: false,
            period: None,
            allow_infeasible: false,
        }),
        ..request(&out)
    };
    let mut hooks = Quiet::default();
    let e = record_trial(&mut board, &req, &mut hooks).unwrap_err();
    assert!(matches!(e, lab::LabError::Faulted(_)), "{e:?}");
    let text = e.chain_text();
    assert!(
        text.starts_with(&format!(
            "the board stopped the robot on a fault: ServoStuck on joint {joint}: servo stuck"
        )) && text.contains(&format!("(joint {name})")),
        "{text}"
    );
    let trials = trials_in(&out);
    assert_eq!(trials.len(), 1, "{trials:?}");
    assert!(trials[0].ends_with(" faulted"), "{trials:?}");
    let path = out.join(&trials[0]);
    assert!(text.contains(&path.display().to_string()), "{text}");
    let trial = board::trial::read_trial(&path).unwrap();
    assert_eq!(trial.meta.outcome, board::trial::Outcome::Faulted);
    let fault = trial
        .meta
        .fault
        .clone()
        .expect("trial.json names the fault");
    assert_eq!(fault.kind, "ServoStuck");
    assert_eq!(fault.joint, Some(joint as u8));
    assert_eq!(fault.joint_name.as_deref(), Some(name.as_str()));
    // The rows up to the fault: every record before it walking (or ramping), the last one the
    // first in the fault state, its cycle the fault's; the walk did not finish its steps.
    let rows = &trial.rows;
    let last = rows.last().unwrap();
    assert_eq!(last.state, Some(protocol::RunState::Fault));
    assert_eq!(fault.cycle, Some(last.cycle));
    assert!(
        rows.iter()
            .filter(|r| r.state == Some(protocol::RunState::Fault))
            .all(|r| r.cycle == last.cycle)
    );
    assert!(trial.meta.cycles > 50, "{} cycles", trial.meta.cycles);
    assert!(last.step < 4, "step {}", last.step);
    let readme = std::fs::read_to_string(path.join("README.md")).unwrap();
    assert!(readme.contains("- outcome: faulted\n"), "{readme}");
    assert!(
        readme.contains(&format!(
            "- fault: {} (joint {name}), first seen in bus cycle {}",
            fault.reason, last.cycle
        )),
        "{readme}"
    );
    // The firmware's build id as the README prints it: the commit's 8 hex digits (firmware's
    // `build_id_is_the_commit_built` checks them against git), never `00000000`.
    let build = match trial.meta.firmware.build_id {
        0 => "unknown".to_owned(),
        id => format!("{id:08x}"),
    };
    assert!(readme.contains(&format!("build {build})")), "{readme}");
    assert!(!readme.contains("build 00000000"), "{readme}");
}

use crate::gate;

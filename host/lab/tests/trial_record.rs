//! `lab::trial_record::record_trial` refuses, in the CLI's words, before anything moves: a trial
//! folder that exists, a perturbation step beyond the steps played, a leg that is not a leg. The
//! virtual robot is still where it was (its state, its counters) and no trial folder appears.

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
        out: out.to_owned(),
        trial: None,
        notes: String::new(),
        substrate: None,
        seconds: None,
        table: None,
        plan: None,
        play: Some(TrialPlay {
            slot: 0,
            steps: Some(2),
            backward: false,
            period: None,
        }),
        strain: None,
        perturb: None,
        platform_id: None,
        every: 1,
        command_line: vec!["test".to_owned()],
        model: planner::model::builtin("drosophibot2").unwrap(),
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

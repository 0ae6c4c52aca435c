//! A plan directory that contradicts itself is refused by the reader, naming what disagrees
//! (issue #30 item 6): plan.json's period or duty edited by hand, or feet.csv's stance flags
//! against plan.json's timing. The unedited directory reads (its own flags are the truth the
//! check is held to: the planner's footpaths).

use std::path::Path;

use lab::plan_dir_write::{PlanSource, write_plan_dir};
use planner::gait::StepParams;
use planner::model::builtin;
use planner::plan::plan;
use planner::plan_dir::{self, PlanJson};

/// The tripod of Drosophibot II with the parameters of the paper's table 1 at 40 slices, written without dynamics into `dir`.
fn write_plan(dir: &Path) -> PlanJson {
    let m = builtin("drosophibot2").unwrap();
    let mut p = StepParams::table1("drosophibot2");
    p.slices = 40;
    let pl = plan(&m, &p).unwrap();
    let source = PlanSource {
        model_source: "drosophibot2",
        table_name: Some("tripod"),
        spring: None,
    };
    write_plan_dir(dir, &pl, &source, None).unwrap();
    plan_dir::read_json(&dir.join("plan.json")).unwrap()
}

fn edit_json(dir: &Path, edit: impl FnOnce(&mut serde_json::Value)) {
    let path = dir.join("plan.json");
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    edit(&mut v);
    std::fs::write(&path, serde_json::to_string_pretty(&v).unwrap()).unwrap();
}

fn read_err(dir: &Path) -> String {
    plan_dir::read(dir).unwrap_err().to_string()
}

#[test]
fn an_unedited_plan_directory_reads() {
    let d = tempfile::tempdir().unwrap();
    let json = write_plan(d.path());
    let pd = plan_dir::read(d.path()).unwrap();
    assert_eq!(pd.json, json);
}

#[test]
fn an_edited_period_is_refused_naming_the_field_and_the_parameters() {
    let d = tempfile::tempdir().unwrap();
    let json = write_plan(d.path());
    edit_json(d.path(), |v| v["period_s"] = (2.0 * json.period_s).into());
    let e = read_err(d.path());
    assert!(
        e.contains("plan.json") && e.contains("period_s") && e.contains("swing_s"),
        "{e}"
    );
    assert!(e.contains("contradicts itself"), "{e}");
}

#[test]
fn an_edited_duty_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let json = write_plan(d.path());
    // A new duty that keeps the period (so only the stance flags and duty disagree): swing_s
    // changed with it, T = swing / (1 - duty).
    let duty = json.parameters.duty - 0.1;
    let swing = json.period_s * (1.0 - duty);
    edit_json(d.path(), |v| {
        v["parameters"]["duty"] = duty.into();
        v["parameters"]["swing_s"] = swing.into();
    });
    let e = read_err(d.path());
    assert!(
        e.contains("feet.csv") && e.contains("slice") && e.contains("duty"),
        "{e}"
    );
    // The duty alone: the period no longer follows from the parameters.
    let d = tempfile::tempdir().unwrap();
    write_plan(d.path());
    edit_json(d.path(), |v| v["parameters"]["duty"] = duty.into());
    let e = read_err(d.path());
    assert!(e.contains("period_s") && e.contains("duty"), "{e}");
}

#[test]
fn stance_flags_that_contradict_the_header_are_refused_naming_slice_and_leg() {
    let d = tempfile::tempdir().unwrap();
    write_plan(d.path());
    let path = d.path().join("feet.csv");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    // A row of slice 5 (an eighth into the cycle: no tripod leg touches down or lifts off
    // there): flip its stance flag (the last column).
    let row = lines.iter_mut().find(|l| l.starts_with("5,")).unwrap();
    let flipped = if row.ends_with(",1") { "0" } else { "1" };
    row.truncate(row.len() - 1);
    row.push_str(flipped);
    let leg = row.split(',').nth(2).unwrap().to_owned();
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    let e = read_err(d.path());
    assert!(
        e.contains("feet.csv") && e.contains("slice 5") && e.contains(&format!("leg {leg}")),
        "{e}"
    );
}

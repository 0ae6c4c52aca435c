//! The feet's sliding friction in the model file (docs/models.md, `foot_friction`): absent it is
//! the ESTIMATE 1.5 the MJCF export always had, given it is the export's contact friction, it
//! round-trips through TOML, and a value outside its range is refused naming file and field.

use planner::model::{
    DEFAULT_FOOT_FRICTION, MjcfOptions, builtin, from_toml_str, to_mjcf, to_toml_string,
};
use planner::terrain::Ground;

const BUILTIN: &str = include_str!("../../models/drosophibot2.toml");

/// The built-in model's text with `foot_friction = mu` after its name.
fn with_friction(mu: &str) -> String {
    let name = "name = \"drosophibot2\"\n";
    assert_eq!(BUILTIN.matches(name).count(), 1);
    BUILTIN.replace(name, &format!("{name}foot_friction = {mu}\n"))
}

/// The sliding coefficient of the MJCF's default geom (the feet's and the terrain's).
fn mjcf_friction(model: &planner::model::Model) -> f64 {
    let options = MjcfOptions::stance(model, &Ground::Flat).unwrap();
    let xml = to_mjcf(model, &options);
    let tail = xml
        .split("<default><geom condim=\"3\" friction=\"")
        .nth(1)
        .unwrap();
    tail.split(' ').next().unwrap().parse().unwrap()
}

#[test]
fn the_feet_friction_is_the_models_and_reaches_the_mjcf() {
    let default = builtin("drosophibot2").unwrap();
    assert_eq!(default.foot_friction, None);
    assert_eq!(default.foot_friction(), 1.5);
    assert_eq!(mjcf_friction(&default), DEFAULT_FOOT_FRICTION);
    let m = from_toml_str(&with_friction("0.55"), "robot.toml").unwrap();
    assert_eq!(m.foot_friction(), 0.55);
    assert_eq!(mjcf_friction(&m), 0.55);
    let again = from_toml_str(&to_toml_string(&m, "", &|_| String::new()), "again.toml").unwrap();
    assert_eq!(again.foot_friction, Some(0.55));
}

#[test]
fn a_foot_friction_out_of_range_is_refused_naming_file_and_field() {
    for bad in ["0.0", "-0.5", "7.0", "nan"] {
        let e = from_toml_str(&with_friction(bad), "robot.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("robot.toml") && e.contains("foot_friction") && e.contains("0.01 ..= 5"),
            "{bad}: {e}"
        );
    }
}

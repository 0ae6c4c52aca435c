//! Bounded versions of the cargo-fuzz targets (fuzz/fuzz_targets/) in the normal suite: the same
//! properties (host/planner/tests/integration/reliability_common/mod.rs) fed with arbitrary bytes and with mutations of
//! valid inputs, plus the regression inputs of every crash fuzzing found.

use crate::reliability_common;
use proptest::collection::vec;
use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;
use reliability_common as checks;

const MODEL: &str = include_str!("../../models/drosophibot2.toml");

/// Text made of `base` with bytes overwritten at random places: valid structure, broken values.
fn mutated(base: &'static str) -> impl Strategy<Value = Vec<u8>> {
    vec((any::<prop::sample::Index>(), any::<u8>()), 1..8).prop_map(move |edits| {
        let mut b = base.as_bytes().to_vec();
        for (at, byte) in edits {
            let i = at.index(b.len());
            b[i] = byte;
        }
        b
    })
}

/// A Dynamixel status packet (a servo's reply) with arbitrary data, encoded properly.
fn status_packet() -> impl Strategy<Value = Vec<u8>> {
    (
        0u8..=252,
        vec(prop_oneof![Just(0xFFu8), Just(0xFD), any::<u8>()], 1..40),
    )
        .prop_map(|(id, params)| {
            let mut buf = [0u8; 256];
            let mut w = dynamixel::encode::PacketWriter::new(&mut buf, id, 0x55).unwrap();
            w.extend(&params);
            let n = w.finish().unwrap();
            buf[..n].to_vec()
        })
}

const PARAM_KEYS: &[&str] = &[
    "swing_s",
    "duty",
    "translation_m",
    "rotation_rad",
    "slices",
    "gait",
    "terrain",
    "ball_radius_m",
    "ball_offset_m",
    "step_height_m",
    "body_height_m",
];

/// A parameter file with a few known keys and hostile values (huge, tiny, negative, NaN, strings).
fn params_file() -> impl Strategy<Value = String> {
    let value = prop_oneof![
        any::<f64>().prop_map(|v| format!("{v:?}")),
        Just("nan".to_string()),
        Just("inf".to_string()),
        Just("1e308".to_string()),
        Just("1e-308".to_string()),
        Just("-0.0".to_string()),
        any::<i64>().prop_map(|v| v.to_string()),
        "[a-z:0-9.]{0,12}".prop_map(|s| format!("{s:?}")),
        (any::<f64>(), any::<f64>(), any::<f64>())
            .prop_map(|(a, b, c)| format!("{{ hind = {a:?}, middle = {b:?}, front = {c:?} }}")),
    ];
    vec((prop::sample::select(PARAM_KEYS), value), 0..6).prop_map(|kv| {
        let mut seen = std::collections::HashSet::new();
        kv.into_iter()
            .filter(|(k, _)| seen.insert(*k))
            .map(|(k, v)| format!("{k} = {v}\n"))
            .collect()
    })
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 500,
        // Regressions are kept beside this file, where proptest reads them back.
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource("proptest-regressions"))),
        ..ProptestConfig::default()
    })]

    #[test]
    fn dxl_status_parser_survives_arbitrary_bytes(data in vec(any::<u8>(), 0..1200)) {
        let _ = checks::dxl_status(&data);
    }

    #[test]
    fn dxl_status_parser_survives_packets_mixed_with_garbage(
        chunk in any::<u8>(),
        parts in vec(prop_oneof![status_packet(), vec(any::<u8>(), 0..20)], 0..20),
    ) {
        let mut data = vec![chunk];
        data.extend(parts.concat());
        let _ = checks::dxl_status(&data);
    }

    #[test]
    fn model_toml_loader_survives_arbitrary_bytes(data in vec(any::<u8>(), 0..400)) {
        let _ = checks::model_toml(&data);
    }

    #[test]
    fn model_toml_loader_survives_mutated_models(data in mutated(MODEL)) {
        let _ = checks::model_toml(&data);
    }

    #[test]
    fn aproj_importer_survives_arbitrary_bytes(data in vec(any::<u8>(), 0..400)) {
        let _ = checks::aproj(&data);
    }

    #[test]
    fn plan_params_survive_arbitrary_bytes(data in vec(any::<u8>(), 0..300)) {
        let _ = checks::plan_params(&data);
    }

    #[test]
    fn plan_params_survive_hostile_values(text in params_file()) {
        let _ = checks::plan_params(text.as_bytes());
    }
}

proptest! {
    // The shared AnimatLab projects are ~300-430 kB of XML: few cases, each a full import.
    #![proptest_config(ProptestConfig {
        cases: 12,
        // Regressions are kept beside this file, where proptest reads them back.
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource("proptest-regressions"))),
        ..ProptestConfig::default()
    })]

    #[test]
    fn aproj_importer_survives_mutated_projects(
        which in 0usize..3,
        edits in vec((any::<prop::sample::Index>(), any::<u8>()), 1..6),
    ) {
        let name = ["Drosobot2", "ScaleDrosophila", "TypicalHexapod"][which];
        let path = format!("{}/../../../shared/models/animatlab/{name}.aproj", env!("CARGO_MANIFEST_DIR"));
        let mut bytes = std::fs::read(&path).unwrap_or_else(|e| {
            panic!("{path}: {e} (the test needs ../shared beside the checkout)")
        });
        for (at, byte) in edits {
            let i = at.index(bytes.len());
            bytes[i] = byte;
        }
        let _ = checks::aproj(&bytes);
    }
}

/// The unmutated inputs satisfy the properties too (and the properties are not vacuous: these
/// inputs are accepted, so the round-trip assertions run).
#[test]
fn valid_inputs_pass_the_checks() {
    assert!(checks::model_toml(MODEL.as_bytes()));
    // The fuzzer's seeds (fuzz/run.sh): the built-in models without comments, notes and sources,
    // numbers to 6 significant digits, and the AnimatLab projects stripped to what is imported.
    for seed in [
        include_str!("../../../../fuzz/seeds/model_toml/drosophibot2.toml"),
        include_str!("../../../../fuzz/seeds/model_toml/scale-drosophila.toml"),
    ] {
        assert!(checks::model_toml(seed.as_bytes()));
    }
    for seed in [
        include_str!("../../../../fuzz/seeds/aproj/Drosobot2.aproj"),
        include_str!("../../../../fuzz/seeds/aproj/ScaleDrosophila.aproj"),
        include_str!("../../../../fuzz/seeds/aproj/TypicalHexapod.aproj"),
    ] {
        assert!(checks::aproj(seed.as_bytes()));
    }
    let params = "swing_s = 0.5\nduty = 0.6\ngait = { phi_i = 0.5, phi_c = 0.5 }\nslices = 40\n";
    assert!(checks::plan_params(params.as_bytes()));
    // e-manual Protocol 2.0, ping example: the status packet of ID 1 (model 1030, firmware 38),
    // arriving in 3-byte chunks.
    let ping_status = [
        3u8, 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x07, 0x00, 0x55, 0x00, 0x06, 0x04, 0x26, 0x65, 0x5D,
    ];
    assert_eq!(checks::dxl_status(&ping_status), 1);
}

/// Regressions found by `plan_params_survive_hostile_values`: parameters that validated although
/// their footpaths overflow to infinity. Each is now refused naming its field.
#[test]
fn parameters_that_overflow_the_footpaths_are_refused_naming_the_field() {
    for (text, field) in [
        ("translation_m = 1e308\n", "translation_m"),
        ("swing_s = 1e300\n", "duty"),
        ("duty = 0.9999999999999999\nswing_s = 1e3\n", "duty"),
        (
            "step_height_m = { hind = 1e300, middle = 0.02, front = 0.02 }\n",
            "step_height_m",
        ),
        (
            "placement = { forward_m = { hind = 0.0, middle = 0.0, front = 0.0 }, \
             outward_m = { hind = 0.1, middle = inf, front = 0.1 } }\n",
            "placement.outward_m",
        ),
    ] {
        let file = planner::gait::ParamsFile::from_toml(text, "p.toml").unwrap();
        let mut p = planner::gait::StepParams::table1("drosophibot2");
        file.apply(&mut p);
        let e = p.validate().expect_err(text).to_string();
        assert!(e.contains(field), "{text}: {e}");
        assert!(!checks::plan_params(text.as_bytes()));
    }
}

/// Regression (proptest, 2026-11): a swing or duty so small that the stance rounds to 0 s passed
/// validation and broke every footpath.
#[test]
fn stance_that_rounds_to_zero_is_rejected() {
    for text in [
        "swing_s = 1e-308\n",
        "duty = 1e-300\n",
        "swing_s = 0.0005\n",
        "swing_s = 0.01\nduty = 0.01\n",
    ] {
        assert!(!checks::plan_params(text.as_bytes()), "{text:?} validated");
    }
    assert!(checks::plan_params(b"swing_s = 0.01\nduty = 0.5\n"));
}

/// Regression (cargo-fuzz `aproj`, 2026-12, `fuzz/artifacts/aproj/crash-154b061e...`): a project
/// with two rigid bodies of one name imported, and the model it gave wrote a model file that does
/// not load ("field `name`: defined twice"). The importer now refuses it naming the body. Here the
/// stripped TypicalHexapod seed with its LM_TrochanterFemur renamed to LM_Coxa, its parent's name.
#[test]
fn a_project_with_two_bodies_of_one_name_is_refused_naming_the_body() {
    let seed = include_str!("../../../../fuzz/seeds/aproj/TypicalHexapod.aproj");
    assert!(checks::aproj(seed.as_bytes()), "the seed itself imports");
    let from = "<Name>LM_TrochanterFemur</Name>";
    assert_eq!(seed.matches(from).count(), 1);
    let text = seed.replace(from, "<Name>LM_Coxa</Name>");
    let opts = planner::model::ImportOptions::default();
    let e = planner::model::import_aproj(&text, "dup.aproj", &opts)
        .expect_err("two bodies named LM_Coxa")
        .to_string();
    assert!(e.contains("dup.aproj") && e.contains("body LM_Coxa"), "{e}");
    assert!(!checks::aproj(text.as_bytes()));
}

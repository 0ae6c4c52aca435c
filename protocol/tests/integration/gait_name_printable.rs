//! Gait names are shown to users as text (issue #30 item 6): the table builder refuses a name
//! with a control character, and a stored name that is not printable text reads as `None`, so
//! every place that shows one says so instead of sending its bytes to the terminal.

use protocol::gait::{BuildError, GaitTableBuilder, JointSpec, ServoModel, Sign, printable_name};

fn builder(name: &str) -> GaitTableBuilder {
    let joint = JointSpec {
        name: "LF_ThC1".into(),
        servo_id: 1,
        model: ServoModel::Mx64,
        sign: Sign::Positive,
        zero_offset: 2048,
        min_rad: -1.0,
        max_rad: 1.0,
        stiffness_nm_per_rad: 8.0,
        leg: None,
    };
    let mut b = GaitTableBuilder::new(name, 1.0, 0.5, vec![joint]);
    b.slice(0, &[0.0], &[0.0]);
    b
}

#[test]
fn a_name_with_a_control_character_is_refused_by_the_builder() {
    // ESC [ 2 J clears a terminal.
    assert_eq!(
        builder("a\u{1b}[2J").header(),
        Err(BuildError::NameNotPrintable { index: 1 })
    );
    assert_eq!(
        builder("tab\there").header(),
        Err(BuildError::NameNotPrintable { index: 3 })
    );
    assert!(
        BuildError::NameNotPrintable { index: 1 }
            .to_string()
            .contains("control character")
    );
    assert_eq!(
        builder("tripod-fwd é").header().unwrap().name_str(),
        Some("tripod-fwd é")
    );
}

#[test]
fn a_stored_name_that_is_not_printable_text_reads_as_none() {
    let mut raw = [0u8; 16];
    raw[..4].copy_from_slice(b"ab\x07c");
    assert_eq!(printable_name(&raw), None);
    raw[..4].copy_from_slice(b"\xff\xfeab");
    assert_eq!(printable_name(&raw), None);
    raw[..4].copy_from_slice(b"abcd");
    assert_eq!(printable_name(&raw), Some("abcd"));
}

//! The properties checked on hostile input, shared by the cargo-fuzz targets (fuzz/fuzz_targets/,
//! which include this file by path) and the bounded proptests of the normal suite
//! (host/planner/tests/integration/reliability_inputs.rs), so that both check exactly the same thing.
//!
//! Each function takes arbitrary bytes, must never panic on bad input, and asserts a property
//! that holds for every input the code under test accepts.
#![allow(dead_code)]

use dynamixel::encode::PacketWriter;
use dynamixel::parser::Parser;
use nalgebra::Vector3;
use planner::gait::{Footpath, GroundMotion, ParamsFile, StepParams};
use planner::model::{ImportOptions, Leg, from_toml_str, import_aproj, to_toml_string, to_urdf};
use planner::terrain::Terrain;

/// Capacity of the parser under test: the bus master's default.
const CAP: usize = dynamixel::parser::DEFAULT_CAPACITY;

/// Dynamixel status parser. The first byte picks the chunk size the rest arrives in. Checks:
/// the parser always takes more bytes or hands out a frame (it never stalls with a full buffer);
/// every accepted frame re-encodes (with stuffing) to a packet that parses to the same frame;
/// after a timeout (`abandon_partial` until empty) the buffer drains in at most one call per
/// buffered byte. Returns the number of valid frames.
pub fn dxl_status(data: &[u8]) -> usize {
    let Some((&first, rest)) = data.split_first() else {
        return 0;
    };
    let mut valid = 0;
    let chunk = usize::from(first).max(1);
    let mut p: Parser = Parser::new();
    for piece in rest.chunks(chunk) {
        let mut piece = piece;
        while !piece.is_empty() {
            let taken = p.feed(piece);
            piece = &piece[taken..];
            let (events, frames) = drain(&mut p);
            valid += frames;
            assert!(
                taken > 0 || events > 0,
                "parser stalled: buffer full ({} bytes) and no frame handed out",
                p.buffered()
            );
            assert!(p.buffered() <= CAP);
        }
    }
    let mut calls = 0;
    let limit = p.buffered() + 1;
    while p.buffered() > 0 {
        p.abandon_partial();
        valid += drain(&mut p).1;
        calls += 1;
        assert!(calls <= limit, "abandon_partial does not drain the buffer");
    }
    valid
}

/// Hands out every complete frame and checks each; returns how many events (frames and rejected
/// packets) there were and how many valid frames among them.
fn drain(p: &mut Parser) -> (usize, usize) {
    let (mut events, mut valid) = (0, 0);
    while let Some(ev) = p.next_frame() {
        events += 1;
        let Ok(f) = ev else { continue };
        valid += 1;
        assert!(f.params.len() < CAP);
        if let Some(st) = f.status() {
            assert_eq!(st.id, f.id);
            assert_eq!(st.data.len() + 1, f.params.len());
        }
        let (id, inst, params) = (f.id, f.instruction, f.params.to_vec());
        let mut buf = [0u8; 2 * CAP];
        let mut w = PacketWriter::new(&mut buf, id, inst).expect("buffer fits a header");
        w.extend(&params);
        // Stuffing may make the packet longer than the parser's buffer: then it is not sent.
        let Ok(n) = w.finish() else { continue };
        if n > CAP {
            continue;
        }
        let mut again: Parser = Parser::new();
        assert_eq!(again.feed(&buf[..n]), n);
        match again.next_frame() {
            Some(Ok(g)) => {
                assert_eq!((g.id, g.instruction, g.params), (id, inst, &params[..]));
            }
            other => panic!("re-encoded frame does not parse back: {other:?}"),
        }
    }
    (events, valid)
}

/// Model TOML loader (returns whether the text loaded). Checks: a model that loads writes back to TOML that loads again with the same
/// bodies, joints and feet, and exports to URDF without panicking.
pub fn model_toml(data: &[u8]) -> bool {
    let Ok(text) = std::str::from_utf8(data) else {
        return false;
    };
    let Ok(model) = from_toml_str(text, "fuzz.toml") else {
        return false;
    };
    let written = to_toml_string(&model, "", &|_| String::new());
    let back = from_toml_str(&written, "written.toml")
        .unwrap_or_else(|e| panic!("a loaded model writes TOML that does not load: {e}"));
    assert_eq!(back.bodies.len(), model.bodies.len());
    assert_eq!(back.joints.len(), model.joints.len());
    assert_eq!(back.feet.len(), model.feet.len());
    let _ = to_urdf(&model);
    true
}

/// AnimatLab importer (returns whether the text imported). Checks: anything imported is a valid model (it writes TOML that loads).
pub fn aproj(data: &[u8]) -> bool {
    let Ok(text) = std::str::from_utf8(data) else {
        return false;
    };
    let Ok(model) = import_aproj(text, "fuzz.aproj", &ImportOptions::default()) else {
        return false;
    };
    let written = to_toml_string(&model, "", &|_| String::new());
    from_toml_str(&written, "imported.toml")
        .unwrap_or_else(|e| panic!("an imported model writes TOML that does not load: {e}"));
    true
}

/// Planner parameters: a parameter file over table 1 of the paper, then validation. Checks: the
/// terrain string parses or is an error; parameters that validate give a finite, positive period
/// and stance and finite foot positions over a whole cycle on flat ground. Returns whether the
/// parameters validated.
pub fn plan_params(data: &[u8]) -> bool {
    let Ok(text) = std::str::from_utf8(data) else {
        return false;
    };
    let Ok(file) = ParamsFile::from_toml(text, "fuzz.toml") else {
        return false;
    };
    let mut params = StepParams::table1("drosophibot2");
    file.apply(&mut params);
    if let Some(t) = &file.terrain {
        let _ = t.plan_terrain(params.ball_radius_m, params.ball_offset_m);
    }
    if params.validate().is_err() {
        return false;
    }
    let (period, stance) = (params.period_s(), params.stance_s());
    assert!(period.is_finite() && period > 0.0, "period {period} s");
    assert!(stance.is_finite() && stance > 0.0, "stance {stance} s");
    let motion = GroundMotion::new(&Terrain::Flat, &params, None);
    let slices = params.slices.min(64);
    for leg in Leg::ALL {
        let rest = Vector3::new(0.1 * leg_sign(leg), 0.15, -0.1);
        let path = Footpath::new(leg, rest, &params, motion);
        for k in 0..slices {
            let (p, _) = path.at(period * k as f64 / slices as f64);
            assert!(
                p.iter().all(|v| v.is_finite()),
                "{leg:?} foot at slice {k}: {p:?} from {params:?}"
            );
        }
    }
    true
}

fn leg_sign(leg: Leg) -> f64 {
    match leg {
        Leg::LH | Leg::RH => -1.0,
        Leg::LM | Leg::RM => 0.0,
        Leg::LF | Leg::RF => 1.0,
    }
}

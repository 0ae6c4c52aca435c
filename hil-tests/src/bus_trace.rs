//! What the board wrote on the servo bus, read back from the emulator's bus trace: the Goal
//! Position Sync Writes, parsed with the dynamixel crate's packet parser.

use crate::emulator::TracedBurst;
use anyhow::{Result, anyhow, ensure};
use dynamixel::control_table::GOAL_POSITION;
use dynamixel::instruction::Instruction;
use dynamixel::parser::Parser;
use std::time::Duration;

/// A Goal Position Sync Write: its burst's start (simulated time) and each servo's goal, ticks,
/// by ID.
pub type GoalWrite = (Duration, Vec<(u8, i32)>);

/// Every Goal Position Sync Write in `bursts`. A corrupt packet is an error: bytes were lost on
/// the wire (e.g. the direction pin low too early), and its goals never reached the servos.
pub fn goal_writes(bursts: &[TracedBurst]) -> Result<Vec<GoalWrite>> {
    parse(bursts, false)
}

/// The same, and every burst must be whole packets, not a byte outside them.
pub fn goal_writes_of_whole_bursts(bursts: &[TracedBurst]) -> Result<Vec<GoalWrite>> {
    parse(bursts, true)
}

fn parse(bursts: &[TracedBurst], whole: bool) -> Result<Vec<GoalWrite>> {
    let mut out = Vec::new();
    for b in bursts {
        let mut parser = Parser::<1024>::new();
        ensure!(
            parser.feed(&b.bytes) == b.bytes.len(),
            "burst at {:?} ({} bytes) longer than the parser holds",
            b.burst.start,
            b.bytes.len()
        );
        while let Some(frame) = parser.next_frame() {
            let f = frame.map_err(|e| {
                anyhow!("corrupt packet in the burst at {:?}: {e:?}", b.burst.start)
            })?;
            if f.instruction != Instruction::SyncWrite as u8 {
                continue;
            }
            // Sync Write parameters (e-manual): address (2, LE), length (2, LE), then per servo
            // its ID and `length` data bytes.
            let p = f.params;
            ensure!(p.len() >= 4, "short Sync Write: {p:?}");
            let addr = u16::from_le_bytes([p[0], p[1]]);
            let len = usize::from(u16::from_le_bytes([p[2], p[3]]));
            if addr != GOAL_POSITION.addr || len != 4 {
                continue;
            }
            let per_servo = p[4..].chunks_exact(1 + len);
            ensure!(
                per_servo.remainder().is_empty(),
                "Sync Write parameters are not whole (ID + 4 bytes) entries: {p:?}"
            );
            let mut goals: Vec<(u8, i32)> = per_servo
                .map(|c| (c[0], i32::from_le_bytes([c[1], c[2], c[3], c[4]])))
                .collect();
            goals.sort_by_key(|g| g.0);
            out.push((b.burst.start, goals));
        }
        ensure!(
            !whole || (parser.skipped_bytes() == 0 && parser.buffered() == 0),
            "burst at {:?}: {} bytes outside whole packets (lost on the wire?)",
            b.burst.start,
            parser.skipped_bytes() as usize + parser.buffered()
        );
    }
    Ok(out)
}

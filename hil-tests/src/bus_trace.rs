//! What the board wrote on the servo bus, read back from the emulator's bus trace: the Goal
//! Position Sync Writes, parsed with the dynamixel crate's packet parser, and whether every packet
//! left the pin as one unbroken run of characters.

use crate::emulator::TracedBurst;
use anyhow::{Result, anyhow, bail, ensure};
use dynamixel::control_table::GOAL_POSITION;
use dynamixel::instruction::Instruction;
use dynamixel::parser::Parser;
use std::time::Duration;

/// A Goal Position Sync Write: its burst's start (simulated time) and each servo's goal, ticks,
/// by ID.
pub type GoalWrite = (Duration, Vec<(u8, i32)>);

/// Checks that no packet the board sent has a gap inside it, and returns how many Sync Writes
/// there were. The runner ends a burst only when the line goes idle (TX FIFO and shift register
/// empty, runner/src/bus.js), so a packet with a pause inside it is cut across two bursts: the
/// first ends in a packet's head (bytes the parser still holds), the next starts with its tail
/// (bytes outside any packet). A servo takes such a pause for the end of the packet (e-manual:
/// status packets and instructions are continuous byte streams), so the cut packet's goals never
/// reach it. A corrupt packet is an error too.
pub fn unbroken_packets(bursts: &[TracedBurst]) -> Result<usize> {
    let mut sync_writes = 0;
    for (i, b) in bursts.iter().enumerate() {
        let parser = packets(b, |f| {
            if f.instruction == Instruction::SyncWrite as u8 {
                sync_writes += 1;
            }
            Ok(())
        })?;
        let head = parser.buffered();
        let stray = parser.skipped_bytes();
        if head > 0 || stray > 0 {
            let gap = |from: &TracedBurst, to: &TracedBurst| {
                to.burst.start.saturating_sub(from.burst.end)
            };
            let (when, idle) = if head > 0 {
                let next = bursts.get(i + 1);
                ("ends", next.map(|n| gap(b, n)))
            } else {
                let prev = i.checked_sub(1).map(|p| &bursts[p]);
                ("starts", prev.map(|p| gap(p, b)))
            };
            let idle = idle.map_or("no burst beside it".to_string(), |d| {
                format!("the line idle for {d:?} between the two")
            });
            bail!(
                "a gap inside a packet: the burst at {:?} ({} bytes, instruction {:?}) {when} in \
                 the middle of a packet ({head} bytes of a packet's head, {stray} bytes outside \
                 any packet), {idle}",
                b.burst.start,
                b.bytes.len(),
                b.burst.instruction,
            );
        }
    }
    Ok(sync_writes)
}

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
        let parser = packets(b, |f| {
            if f.instruction != Instruction::SyncWrite as u8 {
                return Ok(());
            }
            // Sync Write parameters (e-manual): address (2, LE), length (2, LE), then per servo
            // its ID and `length` data bytes.
            let p = f.params;
            ensure!(p.len() >= 4, "short Sync Write: {p:?}");
            let addr = u16::from_le_bytes([p[0], p[1]]);
            let len = usize::from(u16::from_le_bytes([p[2], p[3]]));
            if addr != GOAL_POSITION.addr || len != 4 {
                return Ok(());
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
            Ok(())
        })?;
        ensure!(
            !whole || (parser.skipped_bytes() == 0 && parser.buffered() == 0),
            "burst at {:?}: {} bytes outside whole packets (lost on the wire?)",
            b.burst.start,
            parser.skipped_bytes() as usize + parser.buffered()
        );
    }
    Ok(out)
}

/// Parses `b`'s bytes into packets, handing each to `each`; a corrupt packet is an error. Returns
/// the parser, holding what was left over (a packet's head, bytes outside any packet).
fn packets(
    b: &TracedBurst,
    mut each: impl FnMut(&dynamixel::parser::Frame<'_>) -> Result<()>,
) -> Result<Parser<1024>> {
    let mut parser = Parser::<1024>::new();
    ensure!(
        parser.feed(&b.bytes) == b.bytes.len(),
        "burst at {:?} ({} bytes) longer than the parser holds",
        b.burst.start,
        b.bytes.len()
    );
    while let Some(frame) = parser.next_frame() {
        let f = frame
            .map_err(|e| anyhow!("corrupt packet in the burst at {:?}: {e:?}", b.burst.start))?;
        each(&f)?;
    }
    Ok(parser)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::emulator::BusBurst;

    /// Bursts of `packets` (bytes) sent at 1 Mbit/s: 10 us per character, 100 us apart.
    fn bursts(packets: &[&[u8]]) -> Vec<TracedBurst> {
        let mut at = Duration::ZERO;
        packets
            .iter()
            .map(|p| {
                let end = at + Duration::from_micros(10 * p.len() as u64);
                let b = TracedBurst {
                    burst: BusBurst {
                        start: at,
                        end,
                        len: p.len(),
                        instruction: p.get(7).copied(),
                        answer_end: None,
                    },
                    bytes: p.to_vec(),
                };
                at = end + Duration::from_micros(100);
                b
            })
            .collect()
    }

    fn sync_write() -> Vec<u8> {
        let mut buf = [0u8; 256];
        let n = dynamixel::encode::sync_write_u32(
            &mut buf,
            GOAL_POSITION.addr,
            (1..=22).map(|id| (id, 2048 + u32::from(id))),
        )
        .unwrap();
        buf[..n].to_vec()
    }

    #[test]
    fn whole_sync_writes_pass_and_are_counted() {
        let w = sync_write();
        // 22 servos: 10 header/instruction/CRC bytes + 4 address/length + 22 x 5 = 124 bytes.
        assert_eq!(w.len(), 124);
        assert_eq!(unbroken_packets(&bursts(&[&w, &w])).unwrap(), 2);
    }

    #[test]
    fn a_sync_write_cut_by_an_idle_line_is_a_gap() {
        let w = sync_write();
        let b = bursts(&[&w[..60], &w[60..]]);
        let e = unbroken_packets(&b).unwrap_err().to_string();
        assert!(e.contains("a gap inside a packet"), "{e}");
        // 60 characters of 10 us end at 600 us; the tail starts 100 us later.
        assert!(e.contains("idle for 100"), "{e}");
        // The old check of whole bursts sees it too.
        assert!(goal_writes_of_whole_bursts(&b).is_err());
    }
}

//! What a gait slot holds and lost, in words: a slot that fell back to an older gait because the
//! newer copy was damaged, a slot with only damaged data, a store with no readable record at all.
//! The one place these words are made: `dbot gaits`, `status`, `run`, `record --play`, `upload`
//! and Python's `Board` (`info()["store"]`, a slot's `message`, the fallback warning) say it alike.

use protocol::{GaitSummary, LossReason, LostCopy, SlotInfo};

/// One line about a stored gait: name, shape, timing, CRC.
pub fn describe(g: &GaitSummary) -> String {
    let h = &g.header;
    format!(
        "\"{}\" {} joints x {} slices, step {:.3} s, duty {:.2}, CRC {:#010x}",
        h.name_str().unwrap_or("(name not printable text)"),
        h.joint_count,
        h.slice_count,
        f64::from(h.step_period_us) * 1e-6,
        f64::from(h.duty) * 1e-4,
        g.crc
    )
}

/// The lost copy named: `"tripod-fwd" (seq 7, CRC 0x1234abcd)`, each part only if known.
fn lost_copy(l: &LostCopy) -> String {
    let name = match (l.name, l.name_str()) {
        (Some(_), Some(n)) => format!("\"{n}\""),
        (Some(_), None) => "(name not printable text)".to_owned(),
        (None, _) => "(name unreadable)".to_owned(),
    };
    let mut facts = Vec::new();
    if let Some(seq) = l.seq {
        facts.push(format!("seq {seq}"));
    }
    if let Some(crc) = l.crc {
        facts.push(format!("CRC {crc:#010x}"));
    }
    if facts.is_empty() {
        name
    } else {
        format!("{name} ({})", facts.join(", "))
    }
}

/// What happened to the lost copy, or `None` for a healthy slot. Starts with `FELL BACK` when the
/// slot plays an older gait than the one last committed.
pub fn loss(slot: &SlotInfo) -> Option<String> {
    let l = slot.lost.as_ref()?;
    let copy = lost_copy(l);
    Some(match (l.reason, slot.gait.is_some()) {
        (LossReason::TableChecksum, true) => format!(
            "FELL BACK: the newer copy {copy} failed its CRC check and was lost; the older gait plays"
        ),
        (LossReason::TableChecksum, false) => {
            format!("DAMAGED: its only copy {copy} failed its CRC check and was lost")
        }
        (LossReason::RecordDamaged, true) => format!(
            "MAY HAVE FALLEN BACK: the other copy {copy} has a damaged commit record and was not \
             used; it may have been newer"
        ),
        (LossReason::RecordDamaged, false) => {
            "DAMAGED: no readable record (the commit record is neither erased nor valid)".to_owned()
        }
    })
}

/// The `gaits` line of a slot: its gait (or empty), then what it lost.
pub fn slot_line(slot: &SlotInfo) -> String {
    let gait = slot.gait.as_ref().map(describe);
    match (gait, loss(slot)) {
        (Some(g), None) => format!("slot {}: {g}", slot.slot),
        (Some(g), Some(l)) => format!("slot {}: {g} — {l}", slot.slot),
        (None, Some(l)) => format!("slot {}: {l}", slot.slot),
        (None, None) => format!("slot {}: empty", slot.slot),
    }
}

/// Why `slot` has nothing to play on a board of `slots` slots: beyond the last it is out of
/// range (saying how many there are), else empty.
pub fn no_gait_in(slot: u8, slots: usize) -> String {
    match slots.checked_sub(1) {
        Some(last) if usize::from(slot) > last => {
            format!("no slot {slot}: the board has {slots} slots, 0 ..= {last}")
        }
        Some(_) => format!("slot {slot} is empty; upload a table first"),
        None => format!("no slot {slot}: the board has no gait slots"),
    }
}

/// One line about the whole store when any slot holds damaged data: `store damaged: no readable
/// record` when nothing in it can be read, else which slots lost what.
pub fn store_line(slots: &[SlotInfo]) -> Option<String> {
    let damaged: Vec<&SlotInfo> = slots.iter().filter(|s| s.is_damaged()).collect();
    if damaged.is_empty() {
        return None;
    }
    if damaged.len() == slots.len() && slots.iter().all(|s| s.gait.is_none()) {
        return Some("store damaged: no readable record in any slot".to_owned());
    }
    let which: Vec<String> = damaged
        .iter()
        .map(|s| match (s.gait.is_some(), s.lost.map(|l| l.reason)) {
            (true, Some(LossReason::TableChecksum)) => format!("slot {} fell back", s.slot),
            (true, _) => format!("slot {} may have fallen back", s.slot),
            (false, _) => format!("slot {} has no readable table", s.slot),
        })
        .collect();
    Some(format!("store damaged: {}", which.join(", ")))
}

#[cfg(test)]
mod tests {
    use super::*;
    use protocol::GaitHeader;

    fn name(s: &str) -> [u8; 16] {
        let mut n = [0u8; 16];
        n[..s.len()].copy_from_slice(s.as_bytes());
        n
    }

    fn gait(s: &str) -> GaitSummary {
        GaitSummary {
            header: GaitHeader {
                joint_count: 22,
                slice_count: 40,
                step_period_us: 1_000_000,
                duty: 5000,
                name: name(s),
            },
            crc: 0xAB,
        }
    }

    #[test]
    fn a_fallback_names_both_gaits_and_why() {
        let s = SlotInfo {
            slot: 0,
            gait: Some(gait("tripod-slow")),
            lost: Some(LostCopy {
                seq: Some(7),
                crc: Some(0x1234_ABCD),
                reason: LossReason::TableChecksum,
                name: Some(name("tripod-fwd")),
            }),
        };
        let line = slot_line(&s);
        assert!(line.starts_with("slot 0: \"tripod-slow\""), "{line}");
        assert!(
            line.contains(
                "FELL BACK: the newer copy \"tripod-fwd\" (seq 7, CRC 0x1234abcd) failed its CRC check"
            ),
            "{line}"
        );
        assert_eq!(store_line(&[s]).unwrap(), "store damaged: slot 0 fell back");
    }

    #[test]
    fn a_store_of_unreadable_records_is_damaged_not_empty() {
        let damaged = |slot| SlotInfo {
            slot,
            gait: None,
            lost: Some(LostCopy {
                seq: None,
                crc: None,
                reason: LossReason::RecordDamaged,
                name: None,
            }),
        };
        let slots = [damaged(0), damaged(1)];
        assert_eq!(
            slot_line(&slots[1]),
            "slot 1: DAMAGED: no readable record (the commit record is neither erased nor valid)"
        );
        assert_eq!(
            store_line(&slots).unwrap(),
            "store damaged: no readable record in any slot"
        );
        let empty = SlotInfo {
            slot: 2,
            gait: None,
            lost: None,
        };
        assert_eq!(slot_line(&empty), "slot 2: empty");
        // Beyond the last slot of four: out of range, not empty (issue #30).
        assert_eq!(
            no_gait_in(9, 4),
            "no slot 9: the board has 4 slots, 0 ..= 3"
        );
        assert_eq!(no_gait_in(3, 4), "slot 3 is empty; upload a table first");
        assert_eq!(store_line(&[empty]), None);
    }
}

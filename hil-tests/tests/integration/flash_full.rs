//! Flash full, on the real image: with every gait slot of memory.x's store holding a gait, a table
//! larger than a slot is refused at `UploadBegin` for every slot (before any flash is erased), there
//! is no slot beyond the last, and every stored gait stays listed with its CRC and still plays.

use anyhow::{Context, Result, ensure};
use hil_tests::drive::{T, play_steps, start_with_servos};
use hil_tests::gait::{crc32, sine_gait, upload};
use protocol::message::{DeviceInfo, Direction, SlotInfo, Status};
use protocol::{MAX_CHUNK_LEN, Request, Response};

/// The gait store of memory.x (1.5 MB); the slots share it.
const GAIT_STORE_BYTES: u32 = 1536 * 1024;

fn slots(link: &mut hil_tests::link::Link) -> Result<Vec<SlotInfo>> {
    let v: heapless::Vec<SlotInfo, { protocol::MAX_SLOTS }> =
        link.request(&Request::ListGaits, T)?;
    Ok(v.into_iter().collect())
}

#[test]
fn a_full_gait_store_refuses_what_does_not_fit_and_keeps_every_gait() -> Result<()> {
    let Some((_board, mut link)) =
        start_with_servos("flash_full", env!("CARGO_BIN_EXE_hil-bus"), 22, 1_000_000)?
    else {
        return Ok(());
    };
    let info: DeviceInfo = link.request(&Request::GetDeviceInfo, T)?;
    let n = u8::try_from(info.slots.len())?;
    ensure!(n > 0, "no gait slots: {info:?}");
    ensure!(
        info.slot_capacity * u32::from(n) <= GAIT_STORE_BYTES,
        "{n} slots of {} bytes do not fit memory.x's gait store",
        info.slot_capacity
    );

    // Fill every slot, each with a different gait.
    let mut crcs = Vec::new();
    for slot in 0..n {
        let (builder, table) =
            sine_gait(&format!("full-{slot}"), 40, 0.1 + 0.02 * f64::from(slot))?;
        let r = upload(&mut link, slot, &builder, &table, MAX_CHUNK_LEN, T)?;
        ensure!(
            r == Response::Committed {
                slot,
                crc: crc32(&table)
            },
            "slot {slot}: {r:?}"
        );
        crcs.push(crc32(&table[..table.len() - 4]));
    }

    // A valid header whose table is larger than a slot: 22 joints x 10 000 slices (about 0.9 MB
    // against a slot of a quarter of 1.5 MB). Refused by size, naming the slot's capacity.
    let (small, _) = sine_gait("too-large", 40, 0.1)?;
    let mut header = small.header()?;
    header.slice_count = protocol::gait::MAX_SLICES;
    let total_len = header.table_len();
    ensure!(total_len > info.slot_capacity, "the test table fits a slot");
    for slot in 0..n {
        let e = link
            .request::<Response>(
                &Request::UploadBegin {
                    slot,
                    header,
                    total_len,
                },
                T,
            )
            .err()
            .with_context(|| format!("slot {slot} accepted a {total_len}-byte table"))?;
        let want = format!(
            "TooLarge {{ total_len: {total_len}, capacity: {} }}",
            info.slot_capacity
        );
        ensure!(format!("{e:#}").contains(&want), "slot {slot}: {e:#}");
    }
    // No slot beyond the last.
    let e = link
        .request::<Response>(
            &Request::UploadBegin {
                slot: n,
                header: small.header()?,
                total_len: small.header()?.table_len(),
            },
            T,
        )
        .err()
        .context("a slot beyond the last accepted an upload")?;
    let want = format!("NoSuchSlot {{ slot: {n}, slots: {n} }}");
    ensure!(format!("{e:#}").contains(&want), "{e:#}");

    // The uploads' flash erases stalled the chip while servo replies were due (the board was
    // Idle, reading its servos): no servo may have been reported missing for it.
    let st: Status = link.request(&Request::GetStatus, T)?;
    ensure!(st.fault.is_none(), "a fault after the uploads: {st:?}");
    // Every gait is still there, whole, and the first one walks.
    let listed = slots(&mut link)?;
    for (slot, crc) in crcs.iter().enumerate() {
        let s = listed
            .iter()
            .find(|s| usize::from(s.slot) == slot)
            .with_context(|| format!("slot {slot} not listed"))?;
        let g = s
            .gait
            .with_context(|| format!("slot {slot} lost its gait"))?;
        ensure!(
            g.crc == *crc,
            "slot {slot}: CRC {:#x}, stored {crc:#x}",
            g.crc
        );
    }
    let records = play_steps(&mut link, 0, Direction::Forward, 2)?;
    ensure!(!records.is_empty(), "no telemetry while walking slot 0");
    Ok(())
}

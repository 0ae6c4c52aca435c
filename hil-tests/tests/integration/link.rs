//! The host link of the real firmware image, end to end through USB CDC-ACM: device info, a gait
//! upload verified in the board's slot list and byte for byte in its flash, a reset in the middle of
//! an upload that must leave the old gait intact, and garbage or oversized frames that must be
//! answered with errors while the board keeps serving requests.

use anyhow::{Context, Result, ensure};
use hil_tests::drive::{self, T};
use hil_tests::gait::{crc32, sine_gait, upload};
use hil_tests::link::Link;
use hil_tests::{Options, Target};
use protocol::gait::GaitTableBuilder;
use protocol::message::{DeviceInfo, SlotInfo, Status};
use protocol::{DeviceMessage, FrameError, MAX_CHUNK_LEN, Request, Response};
use std::time::Duration;

const FLASH_SIZE: usize = 2 * 1024 * 1024;
const GAIT_STORE: usize = 0x8_0000;

/// The board on `flash_file` (a fresh flash when `None`), connected and past boot.
fn start(test: &str, flash_file: Option<std::path::PathBuf>) -> Result<Option<(Target, Link)>> {
    let opts = Options {
        flash_file,
        ..Options::default()
    };
    drive::start(test, opts)
}

fn slots(link: &mut Link) -> Result<heapless::Vec<SlotInfo, { protocol::MAX_SLOTS }>> {
    link.request(&Request::ListGaits, T)
}

#[test]
fn device_info_names_this_firmware_and_protocol() -> Result<()> {
    let Some((_board, mut link)) = start("device_info", None)? else {
        return Ok(());
    };
    let info: DeviceInfo = link.request(&Request::GetDeviceInfo, T)?;
    let version: Vec<u16> = env!("CARGO_PKG_VERSION")
        .split('.')
        .map(|p| p.parse().unwrap())
        .collect();
    assert_eq!(
        [
            info.firmware.major,
            info.firmware.minor,
            info.firmware.patch
        ],
        version[..],
        "{info:?}"
    );
    assert_eq!(info.protocol_version, protocol::PROTOCOL_VERSION);
    assert_eq!(usize::from(info.max_chunk_len), MAX_CHUNK_LEN);
    assert!(
        info.capabilities
            .contains(protocol::message::Capabilities::GAIT_STORE)
    );
    // The slots share the 1.5 MB gait store of memory.x.
    assert!(
        info.slot_capacity > 0 && info.slot_capacity as usize * info.slots.len() <= 1536 * 1024
    );
    Ok(())
}

#[test]
fn uploaded_gait_is_listed_and_stored_byte_for_byte_in_flash() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let flash_file = dir.path().join("flash.bin");
    let Some((board, mut link)) = start("upload", Some(flash_file.clone()))? else {
        return Ok(());
    };
    let (builder, table) = upload_committed(&mut link, 1, "hil-upload", 40, 0.3)?;
    ensure_slot_holds(&mut link, 1, &builder, &table)?;
    if let Some(emu) = board.emulator() {
        emu.save_flash()?;
        let flash = std::fs::read(&flash_file)?;
        assert_eq!(flash.len(), FLASH_SIZE);
        let store = &flash[GAIT_STORE..];
        ensure!(
            store.windows(table.len()).any(|w| w == table),
            "the {} table bytes are not in the gait store",
            table.len()
        );
    }
    Ok(())
}

/// Uploads gait A, then starts B into the same slot and resets the chip at B's `nth` flash program
/// operation, cutting that write short after `torn` bytes (power lost mid-write).
fn reset_during_upload(test: &str, nth: u32, torn: Option<u32>) -> Result<()> {
    let dir = tempfile::tempdir()?;
    let Some((board, mut link)) = start(test, Some(dir.path().join("flash.bin")))? else {
        return Ok(());
    };
    let Some(emu) = board.emulator() else {
        return hil_tests::target::skip(test, "resetting mid-write needs the emulator");
    };
    let (a_builder, a) = upload_committed(&mut link, 0, "gait-a", 40, 0.3)?;
    let (b_builder, b) = sine_gait("gait-b", 60, 0.2)?;
    let programs_before = emu.stats()?["flash"]["programs"].as_u64().unwrap_or(0);
    emu.reset_on_flash_program(nth, torn)?;
    // The reset cuts the upload: requests after it go unanswered until the board is back.
    let _ = upload(
        &mut link,
        0,
        &b_builder,
        &b,
        MAX_CHUNK_LEN,
        Duration::from_secs(3),
    );
    let reset = emu.wait_event_n("reset", 1, Duration::from_secs(30))?;
    println!("reset: {reset}");
    let programs = emu.stats()?["flash"]["programs"].as_u64().unwrap_or(0);
    assert!(
        programs > programs_before,
        "B's upload wrote to flash before the reset"
    );
    emu.wait_event_n("usb_configured", 2, Duration::from_secs(30))?;
    emu.run_for(Duration::from_millis(50))?;
    let mut link = Link::open(board.port())?;
    // Slot 0 holds gait A after the reset.
    ensure_slot_holds(&mut link, 0, &a_builder, &a)
}

/// Uploads the sine gait `name` ([`sine_gait`]) into `slot`; the commit must name the slot and
/// the table's CRC-32.
fn upload_committed(
    link: &mut Link,
    slot: u8,
    name: &str,
    slices: usize,
    amp_rad: f64,
) -> Result<(GaitTableBuilder, Vec<u8>)> {
    let (builder, table) = sine_gait(name, slices, amp_rad)?;
    let r = upload(link, slot, &builder, &table, MAX_CHUNK_LEN, T)?;
    let crc = crc32(&table);
    ensure!(
        r == Response::Committed { slot, crc },
        "upload of {name}: {r:?}"
    );
    Ok((builder, table))
}

/// The board lists `slot` holding `table` of `builder`: its header, and the table's own stored
/// CRC (CRC-32 of everything before the table's last 4 bytes).
fn ensure_slot_holds(
    link: &mut Link,
    slot: u8,
    builder: &GaitTableBuilder,
    table: &[u8],
) -> Result<()> {
    let listed = slots(link)?;
    let info = listed
        .iter()
        .find(|s| s.slot == slot)
        .with_context(|| format!("slot {slot} listed"))?;
    let summary = info
        .gait
        .with_context(|| format!("slot {slot} holds no gait"))?;
    ensure!(
        summary.crc == crc32(&table[..table.len() - 4]),
        "slot {slot}: {summary:?}"
    );
    ensure!(
        summary.header == builder.header()?,
        "slot {slot}: {summary:?}"
    );
    Ok(())
}

#[test]
fn reset_at_the_first_flash_write_of_an_upload_keeps_the_old_gait() -> Result<()> {
    reset_during_upload("reset_first_write", 1, None)
}

#[test]
fn reset_mid_write_of_an_upload_keeps_the_old_gait() -> Result<()> {
    reset_during_upload("reset_torn_write", 3, Some(100))
}

/// A fresh board that was sent a garbage frame and an oversized one: its link, the status before,
/// the status after and the rejections the board sent (`None`: the test is skipped).
fn bad_frames_on_a_fresh_board(test: &str) -> Result<Option<BadFrames>> {
    let Some((board, mut link)) = start(test, None)? else {
        return Ok(None);
    };
    let (before, after, rejected) = send_bad_frames(&mut link)?;
    Ok(Some((board, link, before, after, rejected)))
}

type BadFrames = (Target, Link, Status, Status, Vec<FrameError>);

/// Sends a garbage frame and an oversized one; returns the status before, the status after and the
/// rejections the board sent.
fn send_bad_frames(link: &mut Link) -> Result<(Status, Status, Vec<FrameError>)> {
    let before: Status = link.request(&Request::GetStatus, T)?;
    // A COBS-valid frame whose CRC cannot match its contents.
    link.send_raw(&[0x05, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x00])?;
    // Longer than any frame the board accepts, zero-free so it is one frame.
    let oversized = vec![0x42u8; protocol::MAX_FRAME_LEN * 3];
    link.send_raw(&oversized)?;
    link.send_raw(&[0x00])?;
    let after: Status = link.request(&Request::GetStatus, T)?;
    let rejected = link
        .unsolicited
        .iter()
        .filter_map(|m| match m {
            DeviceMessage::Rejected(e) => Some(*e),
            _ => None,
        })
        .collect();
    Ok((before, after, rejected))
}

#[test]
fn garbage_and_oversized_frames_are_rejected_and_the_board_keeps_serving() -> Result<()> {
    let Some((_board, mut link, before, after, rejected)) = bad_frames_on_a_fresh_board("garbage")?
    else {
        return Ok(());
    };
    assert_eq!(
        rejected.len(),
        2,
        "one rejection per bad frame: {rejected:?}"
    );
    assert_eq!(rejected[1], FrameError::TooLong, "{rejected:?}");
    assert_eq!(
        after.state, before.state,
        "bad frames do not change the state"
    );
    // And it still takes a real request that needs work: device info.
    let info: DeviceInfo = link.request(&Request::GetDeviceInfo, T)?;
    assert_eq!(info.protocol_version, protocol::PROTOCOL_VERSION);
    Ok(())
}

#[test]
fn status_counts_rejected_frames() -> Result<()> {
    let Some((_board, _, before, after, _)) = bad_frames_on_a_fresh_board("rejected_counter")?
    else {
        return Ok(());
    };
    assert_eq!(
        after.counters.rejected_frames,
        before.counters.rejected_frames + 2
    );
    Ok(())
}

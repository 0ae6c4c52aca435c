//! The emulator's own guarantees that the firmware tests build on: the flash image it runs is exactly
//! the ELF's loadable segments (checked with the `object` crate, independently of the runner's JS
//! ELF reader), a flash file keeps what lies outside the image (the gait store) across runs and
//! resets, and a reset reboots the firmware with simulated time running on.

use anyhow::{Context, Result};
use hil_tests::{Options, Target};
use object::read::elf::{FileHeader, ProgramHeader};
use std::time::Duration;

const FLASH_BASE: u64 = 0x1000_0000;
const FLASH_SIZE: usize = 2 * 1024 * 1024;
/// Gait store offset from memory.x (GAITS ORIGIN 0x10080000).
const GAIT_STORE: usize = 0x8_0000;

/// (flash offset, bytes) of every PT_LOAD segment with file contents in the flash window.
fn elf_flash_segments(elf: &[u8]) -> Result<Vec<(usize, Vec<u8>)>> {
    let header = object::elf::FileHeader32::<object::Endianness>::parse(elf)?;
    let endian = header.endian()?;
    let mut out = Vec::new();
    for ph in header.program_headers(endian, elf)? {
        let paddr = u64::from(ph.p_paddr(endian));
        if ph.p_type(endian) == object::elf::PT_LOAD
            && ph.p_filesz(endian) > 0
            && (FLASH_BASE..FLASH_BASE + FLASH_SIZE as u64).contains(&paddr)
        {
            let data = ph
                .data(endian, elf)
                .map_err(|()| anyhow::anyhow!("segment data"))?;
            out.push(((paddr - FLASH_BASE) as usize, data.to_vec()));
        }
    }
    Ok(out)
}

#[test]
fn flash_file_holds_the_elf_image_and_keeps_the_gait_store_across_a_reset() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let flash_file = dir.path().join("flash.bin");
    // A previous "board life": erased flash with a recognisable pattern in the gait store.
    let mut before = vec![0xFFu8; FLASH_SIZE];
    let pattern: Vec<u8> = (0..4096u32).map(|i| (i * 31 + 7) as u8).collect();
    before[GAIT_STORE..GAIT_STORE + pattern.len()].copy_from_slice(&pattern);
    std::fs::write(&flash_file, &before)?;
    let opts = Options {
        flash_file: Some(flash_file.clone()),
        ..Options::default()
    };
    let Some(board) = Target::start("flash_file", opts)? else {
        return Ok(());
    };
    let Some(emu) = board.emulator() else {
        return hil_tests::target::skip("flash_file", "emulator-only test");
    };
    emu.wait_for_log("drosophibot firmware", Duration::from_secs(2))?;
    emu.reset()?;
    emu.run_for(Duration::from_millis(50))?;
    let banners = emu
        .logs()
        .iter()
        .filter(|l| l.text.contains("drosophibot firmware"))
        .count();
    assert_eq!(banners, 2, "the firmware booted again after the reset");
    emu.save_flash()?;
    let after = std::fs::read(&flash_file)?;
    assert_eq!(after.len(), FLASH_SIZE);
    assert_eq!(
        &after[GAIT_STORE..GAIT_STORE + pattern.len()],
        &pattern[..],
        "gait store kept"
    );
    let elf = std::fs::read(hil_tests::paths::firmware_elf()).context("firmware ELF")?;
    let segments = elf_flash_segments(&elf)?;
    assert!(!segments.is_empty());
    for (offset, data) in &segments {
        assert_eq!(
            &after[*offset..offset + data.len()],
            &data[..],
            "flash at {offset:#x} holds the ELF segment"
        );
    }
    Ok(())
}

#[test]
fn simulated_time_runs_on_across_a_reset_and_usb_enumerates_again() -> Result<()> {
    let Some(board) = Target::start("reset_time", Options::default())? else {
        return Ok(());
    };
    let Some(emu) = board.emulator() else {
        return hil_tests::target::skip("reset_time", "emulator-only test");
    };
    emu.wait_event_n("usb_configured", 1, Duration::from_secs(30))?;
    let t0 = emu.run_for(Duration::from_millis(100))?;
    emu.reset()?;
    let reset = emu.wait_event_n("reset", 1, Duration::from_secs(30))?;
    let at = Duration::from_nanos(reset["sim_ns"].as_f64().unwrap_or(0.0) as u64);
    assert!(at >= t0, "reset at {at:?} is not before {t0:?}");
    let again = emu.wait_event_n("usb_configured", 2, Duration::from_secs(30))?;
    let configured = Duration::from_nanos(again["sim_ns"].as_f64().unwrap_or(0.0) as u64);
    // rp2040js's host side waits 10 ms after the firmware enables USB before its bus reset, so
    // enumeration after a reset cannot finish sooner than that.
    assert!(
        configured >= at + Duration::from_millis(10),
        "{configured:?} vs reset {at:?}"
    );
    Ok(())
}

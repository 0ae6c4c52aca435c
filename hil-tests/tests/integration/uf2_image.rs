//! Flashing without a probe (docs/hardware.md, "Flashing"): the release image converted to UF2 with
//! `elf2flash convert --board rp2040` (what the page tells a lab to run) is checked here against
//! the UF2 specification (Microsoft's UF2 README: 512-byte blocks, the two start magics and the end
//! magic, the family ID flag 0x2000) and against the ELF itself: every loadable byte of the image
//! is in a block at its flash address, blocks are numbered in order with the right count, the
//! family is the RP2040's (0xE48BFF56), and no block reaches the gait store (`memory.x`: GAITS at
//! 0x1008_0000), so flashing keeps the stored gaits.

use anyhow::{Context, Result, bail, ensure};
use hil_tests::paths::firmware_elf;
use hil_tests::target::missing;
use object::Endianness;
use object::elf::{FileHeader32, PT_LOAD};
use object::read::elf::{FileHeader, ProgramHeader};
use std::collections::BTreeMap;
use std::process::Command;

const MAGIC_START0: u32 = 0x0A32_4655;
const MAGIC_START1: u32 = 0x9E5D_5157;
const MAGIC_END: u32 = 0x0AB1_6F30;
const FLAG_FAMILY_ID: u32 = 0x0000_2000;
const RP2040_FAMILY: u32 = 0xE48B_FF56;
const FLASH_START: u64 = 0x1000_0000;
const GAITS_START: u64 = 0x1008_0000;

fn word(block: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(block[at..at + 4].try_into().unwrap())
}

#[test]
fn the_uf2_file_holds_every_loadable_byte_of_the_image_and_nothing_of_the_gait_store() -> Result<()>
{
    let test = "uf2_image";
    let elf = firmware_elf();
    if !elf.is_file() {
        return missing(test, &format!("no firmware image at {}", elf.display()));
    }
    let dir = tempfile::tempdir()?;
    let uf2 = dir.path().join("firmware.uf2");
    let out = match Command::new("elf2flash")
        .args(["convert", "--verbose", "off", "--board", "rp2040"])
        .arg(&elf)
        .arg(&uf2)
        .output()
    {
        Ok(o) => o,
        Err(e) => return missing(test, &format!("elf2flash: {e} (cargo install elf2flash)")),
    };
    ensure!(
        out.status.success(),
        "elf2flash convert failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let bytes = std::fs::read(&uf2)?;
    ensure!(
        !bytes.is_empty() && bytes.len() % 512 == 0,
        "{} bytes: not whole 512-byte blocks",
        bytes.len()
    );
    // Flash contents by address, from the UF2 blocks.
    let blocks = bytes.len() / 512;
    let mut flash: BTreeMap<u64, u8> = BTreeMap::new();
    for (n, b) in bytes.chunks_exact(512).enumerate() {
        ensure!(
            (word(b, 0), word(b, 4), word(b, 508)) == (MAGIC_START0, MAGIC_START1, MAGIC_END),
            "block {n}: magic numbers"
        );
        ensure!(
            word(b, 8) & FLAG_FAMILY_ID != 0,
            "block {n}: no family ID flag"
        );
        ensure!(
            word(b, 28) == RP2040_FAMILY,
            "block {n}: family {:#x}",
            word(b, 28)
        );
        let (addr, size) = (u64::from(word(b, 12)), word(b, 16) as usize);
        ensure!(
            (word(b, 20) as usize, word(b, 24) as usize) == (n, blocks),
            "block {n}: numbered {} of {}",
            word(b, 20),
            word(b, 24)
        );
        ensure!(size <= 476, "block {n}: payload {size}");
        ensure!(
            addr >= FLASH_START && addr + size as u64 <= GAITS_START,
            "block {n}: {addr:#x}+{size} outside the image's flash (the gait store starts at {GAITS_START:#x})"
        );
        for (i, v) in b[32..32 + size].iter().enumerate() {
            if flash.insert(addr + i as u64, *v).is_some() {
                bail!("block {n}: address {:#x} written twice", addr + i as u64);
            }
        }
    }
    // Every loadable byte of the ELF at its load (physical) address: .text and .rodata where they
    // run, .data's initial values where the start-up code copies them from (its p_vaddr is RAM).
    let data = std::fs::read(&elf)?;
    let header = FileHeader32::<Endianness>::parse(&*data).context("parsing the firmware ELF")?;
    let endian = header.endian()?;
    let mut checked = 0usize;
    for ph in header.program_headers(endian, &*data)? {
        if ph.p_type(endian) != PT_LOAD || ph.p_filesz(endian) == 0 {
            continue;
        }
        let load = u64::from(ph.p_paddr(endian));
        let content = ph
            .data(endian, &*data)
            .map_err(|()| anyhow::anyhow!("a segment's bytes lie outside the ELF file"))?;
        ensure!(
            (FLASH_START..GAITS_START).contains(&load),
            "a loadable segment at {load:#x} outside the image's flash"
        );
        for (i, v) in content.iter().enumerate() {
            let a = load + i as u64;
            ensure!(
                flash.get(&a) == Some(v),
                "ELF byte at {a:#x} is {v:#04x}, the UF2 has {:?}",
                flash.get(&a)
            );
        }
        checked += content.len();
    }
    ensure!(
        checked > 10_000,
        "only {checked} loadable bytes found in the ELF"
    );
    println!(
        "{blocks} UF2 blocks, {} flash bytes; {checked} loadable ELF bytes match",
        flash.len()
    );
    Ok(())
}

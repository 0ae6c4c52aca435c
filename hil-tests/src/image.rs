//! Flash and RAM use of a firmware ELF image, checked against the budget of the firmware issue.

use anyhow::{Context, Result, bail};
use object::Endianness;
use object::elf::{FileHeader32, PT_LOAD, SHF_ALLOC};
use object::read::elf::{FileHeader, ProgramHeader, SectionHeader};

/// XIP flash window of the RP2040.
const FLASH: std::ops::Range<u64> = 0x1000_0000..0x1100_0000;
/// SRAM of the RP2040 (including the SRAM4/5 banks).
const RAM: std::ops::Range<u64> = 0x2000_0000..0x2004_2000;

/// What an image occupies, in bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Usage {
    /// Bytes loaded into flash: code, read-only data and the `.data` load image.
    pub flash: u64,
    /// Bytes of RAM reserved statically: `.data`, `.bss`, `.uninit` (the stack is what remains).
    pub ram: u64,
}

/// The firmware issue's budget: flash for code under 256 KB, static RAM under 64 KB.
pub const BUDGET: Usage = Usage {
    flash: 256 * 1024,
    ram: 64 * 1024,
};

/// Reads an ELF32 image and sums what it puts in flash (by load address) and in RAM.
pub fn usage(elf: &[u8]) -> Result<Usage> {
    let header = FileHeader32::<Endianness>::parse(elf).context("not an ELF32 file")?;
    let endian = header.endian().context("bad ELF endianness")?;
    if endian != Endianness::Little {
        bail!("expected a little-endian ARM image");
    }
    let mut usage = Usage { flash: 0, ram: 0 };
    for ph in header
        .program_headers(endian, elf)
        .context("bad program headers")?
    {
        if ph.p_type(endian) == PT_LOAD && FLASH.contains(&u64::from(ph.p_paddr(endian))) {
            usage.flash += u64::from(ph.p_filesz(endian));
        }
    }
    let sections = header
        .sections(endian, elf)
        .context("bad section headers")?;
    for section in sections.iter() {
        let alloc = section.sh_flags(endian) & SHF_ALLOC != 0;
        if alloc && RAM.contains(&u64::from(section.sh_addr(endian))) {
            usage.ram += u64::from(section.sh_size(endian));
        }
    }
    Ok(usage)
}

/// Reads an image file, prints its use against the budget and fails when it is over.
pub fn report(path: &std::path::Path) -> Result<Usage> {
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
    let u = usage(&bytes).with_context(|| format!("{}", path.display()))?;
    println!(
        "firmware image {}: flash {:.1} KB of {} KB budget, static RAM {:.1} KB of {} KB budget",
        path.display(),
        u.flash as f64 / 1024.0,
        BUDGET.flash / 1024,
        u.ram as f64 / 1024.0,
        BUDGET.ram / 1024
    );
    if u.flash > BUDGET.flash || u.ram > BUDGET.ram {
        bail!("firmware image is over budget: {u:?} > {BUDGET:?}");
    }
    Ok(u)
}

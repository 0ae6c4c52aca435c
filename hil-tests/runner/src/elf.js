//! ELF32 reader for the firmware image: the flash contents from the PT_LOAD segments (by physical,
//! i.e. load, address, so `.data`'s initial values land where the reset handler copies them from) and
//! symbol addresses from `.symtab` (for `_SEGGER_RTT`). No llvm-objcopy needed.

const PT_LOAD = 1;
const SHT_SYMTAB = 2;

/** Parses an ELF32 little-endian image; throws naming the problem when it is not one. */
export function parseElf(bytes) {
  const buf = Buffer.isBuffer(bytes) ? bytes : Buffer.from(bytes);
  if (buf.length < 52 || buf.readUInt32BE(0) !== 0x7f454c46) {
    throw new Error('not an ELF file (bad magic)');
  }
  if (buf[4] !== 1) throw new Error('not a 32-bit ELF file (EI_CLASS != ELFCLASS32)');
  if (buf[5] !== 1) throw new Error('not a little-endian ELF file (EI_DATA != ELFDATA2LSB)');
  const phoff = buf.readUInt32LE(28);
  const shoff = buf.readUInt32LE(32);
  const phentsize = buf.readUInt16LE(42);
  const phnum = buf.readUInt16LE(44);
  const shentsize = buf.readUInt16LE(46);
  const shnum = buf.readUInt16LE(48);
  const segments = [];
  for (let i = 0; i < phnum; i++) {
    const o = phoff + i * phentsize;
    if (o + 32 > buf.length) throw new Error(`program header ${i} lies outside the file`);
    const type = buf.readUInt32LE(o);
    const offset = buf.readUInt32LE(o + 4);
    const paddr = buf.readUInt32LE(o + 12);
    const filesz = buf.readUInt32LE(o + 16);
    if (type !== PT_LOAD || filesz === 0) continue;
    if (offset + filesz > buf.length) {
      throw new Error(`PT_LOAD segment ${i} (offset ${offset}, size ${filesz}) lies outside the file`);
    }
    segments.push({ paddr, data: buf.subarray(offset, offset + filesz) });
  }
  const symbols = new Map();
  for (let i = 0; i < shnum; i++) {
    const o = shoff + i * shentsize;
    if (o + 40 > buf.length) break;
    if (buf.readUInt32LE(o + 4) !== SHT_SYMTAB) continue;
    const symOff = buf.readUInt32LE(o + 16);
    const symSize = buf.readUInt32LE(o + 20);
    const strIndex = buf.readUInt32LE(o + 24);
    const strOff = buf.readUInt32LE(shoff + strIndex * shentsize + 16);
    for (let s = symOff; s + 16 <= symOff + symSize; s += 16) {
      const nameOff = buf.readUInt32LE(s);
      if (nameOff === 0) continue;
      const end = buf.indexOf(0, strOff + nameOff);
      const name = buf.toString('latin1', strOff + nameOff, end);
      symbols.set(name, buf.readUInt32LE(s + 4));
    }
  }
  return { segments, symbols };
}

/** Writes the segments that fall in the XIP flash window into a flash array (offset 0 = 0x1000_0000). */
export function loadFlash(elf, flash, flashBase = 0x10000000) {
  let loaded = 0;
  for (const { paddr, data } of elf.segments) {
    if (paddr < flashBase || paddr >= flashBase + flash.length) continue;
    const offset = paddr - flashBase;
    if (offset + data.length > flash.length) {
      throw new Error(`segment at 0x${paddr.toString(16)} (${data.length} bytes) overruns the flash`);
    }
    flash.set(data, offset);
    loaded += data.length;
  }
  if (loaded === 0) throw new Error('the ELF has no PT_LOAD segment in flash (0x10000000..)');
  return loaded;
}
